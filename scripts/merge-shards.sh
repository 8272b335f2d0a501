#!/bin/sh
# Merges the CSVs of an experiment run as N shards (--shard 1/N ... N/N) into
# the CSVs of the unsharded run:
#   scripts/merge-shards.sh OUT.csv SHARD1.csv SHARD2.csv ... SHARDN.csv
# SHARDk.csv is a shard's main CSV (its --out); its side tables
# (<stem>_<table>.csv) are merged into <OUT stem>_<table>.csv, and its other
# side files (e.g. <stem>_*.obj, one cell's each) are copied across.
#
# The key is <SHARDk.csv>.cells, written by every shard (lib/io/sweep.h):
# "shard I N C MODE", "tables - side1 ...", then per cell the shard ran its
# global index and the rows it wrote to each table (then its sweep, hint and
# measured seconds, which the merge does not read). The merge checks that the
# shards are the N shards of one run (the same N, cell count C, assignment
# MODE and tables, each I once) and that every cell 0 .. C-1 is listed by
# exactly one shard (in increasing order within it); it then walks c = 0 .. C-1
# and copies that cell's rows from the shard that ran it: the rows come back
# in cell order, the order of the unsharded run. It also writes OUT.csv.cells,
# all shards' cell lines in cell order (for scripts/calibrate-hints). The
# header (provenance) is shard 1's; the shards' headers must agree apart from
# the lines that describe where and when a shard ran rather than what it ran
# ("# date:", "# command:", "# threads_observed:", "# cpu_lock:", "# cpu:",
# "# cores:"); where one of the last four differs, the merged header keeps
# shard 1's and adds "# shard K <line>" for each other shard's. Every row must have the
# header row's number of fields and the file must end with a newline (a shard
# cut mid-row is refused). Nothing is written unless every table merges: the
# tables go to temporary files that are renamed only at the end. Shards may be
# given in any order. Paths may hold spaces and quotes (not newlines); the
# output may not be one of the inputs (a shard's CSV, side table or cell list).
set -eu
[ $# -ge 2 ] || { echo "usage: $0 OUT.csv SHARD1.csv ... SHARDN.csv" >&2; exit 1; }
out=$1; shift
n=$#
die() { echo "merge-shards: $*" >&2; exit 1; }
# lists of paths are newline-separated and split on newlines only, never globbed
nl='
'
set -f
for s in "$out" "$@"; do case $s in *"$nl"*) die "a path holds a newline: not supported" ;; esac; done
# order the shards by the I in their .cells files
ordered=""
tables=""
cells=""
mode=""
i=1
while [ "$i" -le "$n" ]; do
  found=""
  for s in "$@"; do
    [ -f "$s.cells" ] || die "$s.cells: missing (was $s written with --shard?)"
    read -r word si sn sc smode < "$s.cells" || die "$s.cells: empty"
    [ "$word" = shard ] || die "$s.cells: not a shard cell list"
    [ "$sn" = "$n" ] || die "$s: shard of $sn, but $n shard files were given"
    [ -z "$cells" ] || [ "$sc" = "$cells" ] || die "$s: $sc cells, another shard has $cells (different runs?)"
    [ -z "$mode" ] || [ "$smode" = "$mode" ] || die "$s: --shard-mode ${smode:-(none)}, another shard has $mode (different runs?)"
    cells=$sc
    mode=${smode:-(none)}
    t=$(sed -n 2p "$s.cells")
    [ -z "$tables" ] || [ "$t" = "$tables" ] || die "$s: tables '$t' differ from '$tables'"
    tables=$t
    if [ "$si" = "$i" ]; then [ -z "$found" ] || die "two files are shard $i"; found=$s; fi
  done
  [ -n "$found" ] || die "no file is shard $i of $n"
  ordered="$ordered$nl$found"
  i=$((i + 1))
done
IFS=$nl
# shellcheck disable=SC2086 # newline-separated
set -- ${ordered#"$nl"}
IFS=' 	'
lists=""
for s in "$@"; do lists="$lists$s$nl"; done
ostem=${out%.*}
# every output is written to a temporary file first; none is renamed unless all merged
pending=""
trap 'IFS=$nl; for p in $pending; do rm -f "$p"; done' EXIT
trap 'exit 1' INT TERM HUP
j=0
for t in ${tables#tables }; do
  j=$((j + 1))
  if [ "$t" = - ]; then dst=$out; else dst=${ostem}_$t.csv; fi
  files=""
  for s in "$@"; do
    if [ "$t" = - ]; then f=$s; else f=${s%.*}_$t.csv; fi
    [ -f "$f" ] || die "$f: missing"
    [ -z "$(tail -c 1 "$f")" ] || die "$f: does not end with a newline (cut mid-row?)"
    files="$files$f$nl"
  done
  mkdir -p "$(dirname "$dst")"
  tmp=$dst.merge.$$
  pending="$pending$nl$tmp"
  ctmp=$out.cells.merge.$$
  [ "$j" != 1 ] || pending="$pending$nl$ctmp"
  # the paths go through the environment: awk -v would read backslashes in them as escapes
  FILES=$files LISTS=$lists CELLSOUT=$ctmp awk -v n="$n" -v cells="$cells" -v col="$j" '
    function fail(msg) { print "merge-shards: " msg > "/dev/stderr"; bad = 1; exit 1 }
    function env(line) { return line ~ /^# (date|command|threads_observed|cpu_lock|cpu|cores):/ }
    function key(line) { sub(/:.*/, "", line); return line }
    function nfields(line,   t) { t = line; gsub(/"[^"]*"/, "", t); return gsub(/,/, ",", t) + 1 }
    BEGIN {
      split(ENVIRON["FILES"], F, "\n"); split(ENVIRON["LISTS"], L, "\n"); cellsout = ENVIRON["CELLSOUT"]
      for (s = 1; s <= n; s++) {
        L[s] = L[s] ".cells"; getline x < L[s]; getline x < L[s]   # "shard ..." and "tables ..."
        h = ""
        m = 0
        while ((r = getline line < F[s]) > 0) {
          if (s == 1) H[++nh] = line
          if (!env(line)) h = h line "\n"
          else if (s > 1 && E[key(line)] != line && line !~ /^# (date|command):/) X[++nx] = "# shard " s " " substr(line, 3) # the environment as it was
          else if (s == 1) E[key(line)] = line
          if (line !~ /^#/) break
        }
        if (r <= 0) fail(F[s] ": no header row")
        if (s == 1) { h1 = h; width = nfields(line) }
        else if (h != h1) fail(F[s] ": header differs from " F[1] " (other than the date, command, cpu, cores, cpu_lock and threads_observed lines)")
      }
      # which shard ran each cell: every cell exactly once, in increasing order within a shard
      for (s = 1; s <= n; s++) {
        last = -1
        while ((r = getline rec < L[s]) > 0) {
          split(rec, R, " ")
          c = R[1]
          if (c !~ /^[0-9]+$/ || c + 0 >= cells + 0) fail(L[s] ": cell \"" c "\" is not one of the " cells " cells 0 .. " cells - 1)
          c += 0
          if (c in owner) fail("cell " c " is listed by two shards (" L[owner[c]] " and " L[s] ")")
          if (c <= last) fail(L[s] ": cell " c " after cell " last " (not in cell order)")
          last = c
          owner[c] = s
          rows[c] = R[col + 1]
          if (col == 1) line_of[c] = rec
        }
        if (r < 0) fail(L[s] ": cannot read")
      }
      for (c = 0; c < cells; c++) if (!(c in owner)) fail("cell " c " is listed by no shard (a shard missing or cut short?)")
      if (col == 1) for (c = 0; c < cells; c++) print line_of[c] > cellsout
      for (k = 1; k < nh; k++) print H[k]
      for (k = 1; k <= nx; k++) print X[k]
      print H[nh]
      for (c = 0; c < cells; c++) {
        s = owner[c]
        for (k = 0; k < rows[c]; k++) {
          if ((getline line < F[s]) <= 0) fail(F[s] ": fewer rows than " L[s] " lists")
          if (nfields(line) != width) fail(F[s] ": a row of " nfields(line) " fields under a header of " width " (cut mid-row?): " substr(line, 1, 60))
          print line
        }
      }
      for (s = 1; s <= n; s++)
        if ((getline line < F[s]) > 0) fail(F[s] ": more rows than " L[s] " lists")
    }' > "$tmp" || exit 1
  done_list="${done_list:-}$nl$dst"
done
# other side files (one cell's each, so the shards' names do not collide), also via temporary copies
set +f
for s in "$@"; do
  stem=${s%.*}
  for f in "${stem}"_*; do
    [ -f "$f" ] || continue
    case $f in *.csv|*.cells|*.tmp.*) continue ;; esac
    dst=${ostem}${f#"$stem"}
    tmp=$dst.merge.$$
    if [ -f "$tmp" ]; then # two shards wrote it (a file every shard writes): one copy, if they agree
      cmp -s "$f" "$tmp" || die "$f differs from another shard's file of that name"
      continue
    fi
    pending="$pending$nl$tmp"
    cp "$f" "$tmp" || die "$f: cannot copy to $tmp"
    done_list="$done_list$nl$dst"
  done
done
set -f
{ printf 'shard 1 1 %s %s\n' "$cells" "$mode"; sed -n 2p "$1.cells"; cat "$out.cells.merge.$$"; } > "$out.cells.merge.$$.all" ||
  die "$out.cells: cannot write"
pending="$pending$nl$out.cells.merge.$$.all"
mv "$out.cells.merge.$$.all" "$out.cells.merge.$$"
done_list="$done_list$nl$out.cells"
IFS=$nl
# an output that is one of the inputs would be replaced by the merge, which could then never run again
for dst in $done_list; do
  for s in "$@"; do
    stem=${s%.*}
    set +f
    for f in "$s" "$s.cells" "${stem}"_*; do
      [ ! -e "$f" ] || [ ! "$dst" -ef "$f" ] || die "the output $dst is the input $f; merge into another path (nothing written)"
    done
    set -f
  done
done
for dst in $done_list; do mv "$dst.merge.$$" "$dst"; done
pending=""
