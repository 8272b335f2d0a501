#!/bin/sh
# The CSV convention (docs/csv.md) on every CSV the
# experiments write. Every file: its '#' provenance lines first, then one
# header row, then rows with as many fields as the header. Every column name
# is snake_case and textual, or ends in a unit suffix, or is a listed
# dimensionless name (docs/csv_columns.txt holds the three lists). Every
# data cell is empty (not applicable, not measured), a finite number, `nan`,
# `inf` or `-inf` (computed, not finite), or, in a textual column only, a
# word; never `-nan`, `NaN`, `Inf`, `infinity`, ... A column whose name has
# `_each_` in it (wall_each_ms: every repeat of a timing) holds a list of such
# numbers separated by ';'.
#
#   tests/csv_convention.sh [--quick|--smoke]  the self-test, then every experiment's
#                                         --quick (--smoke) run and two simulate runs, checked
#   tests/csv_convention.sh --runs DIR    the same on the experiments' CSVs already in DIR
#                                         (make check: tests/experiments.sh --smoke DIR)
#   tests/csv_convention.sh --self-test   the checker on constructed good and bad CSVs
#   tests/csv_convention.sh --results DIR the experiments' CSVs in DIR (DIR/<name>.csv,
#                                         DIR/<name>_*.csv) and DIR/movies/*/*.csv
#   tests/csv_convention.sh FILE...       those files
# Run from anywhere (make check: BUILD=<dir> tests/csv_convention.sh --runs DIR).
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
B=${BUILD:-build}
case $B in /*) ;; *) B=$(pwd)/$B ;; esac
LIST=${CSV_COLUMNS:-$root/docs/csv_columns.txt}

# check FILE...: prints "file:line: problem" for each violation (at most 5 a file); exit 1 if any
check() {
  awk -v list="$LIST" '
    function glob_re(p) { gsub(/[.]/, "[.]", p); gsub(/[*]/, ".*", p); return "^" p "$" } # names are [a-z0-9_*]
    function bad(msg) { nerr++; if (++ferr <= 5) printf "%s:%d: %s\n", FILENAME, FNR, msg; else if (ferr == 6) printf "%s: (more)\n", FILENAME }
    function classify(name,   k) {
      for (k = 1; k <= ntext; k++) if (name ~ text[k]) return "text"
      for (k = 1; k <= nunit; k++) if (length(name) > length(unit[k]) + 1 && substr(name, length(name) - length(unit[k])) == "_" unit[k]) return "unit"
      for (k = 1; k <= nfree; k++) if (name ~ unitless[k]) return "unitless"
      return ""
    }
    BEGIN {
      while ((getline line < list) > 0) {
        if (line ~ /^[ \t]*(#|$)/) continue
        split(line, w, /[ \t]+/)
        if (w[1] == "unit") unit[++nunit] = w[2]
        else if (w[1] == "text") text[++ntext] = glob_re(w[2])
        else if (w[1] == "unitless") unitless[++nfree] = glob_re(w[2])
        else { printf "%s: unknown kind %s\n", list, w[1]; exit 2 }
      }
      if (!nunit || !ntext || !nfree) { printf "%s: missing or incomplete\n", list; exit 2 }
      FS = ","
      num = "^-?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$"
    }
    FNR == 1 { if (NR > 1 && !hdr) { printf "%s: no header row\n", prev; nerr++ } hdr = 0; ferr = 0; prev = FILENAME; nfiles++ }
    /^#/ { if (hdr) bad("a # line after the header row (provenance lines come first)"); next }
    $0 == "" { bad("an empty line"); next }
    !hdr {
      hdr = 1; ncol = NF; delete seen
      for (i = 1; i <= NF; i++) {
        col[i] = $i; kind[i] = classify($i)
        if ($i !~ /^[a-z][a-z0-9_]*$/) bad("column \"" $i "\": not a snake_case name")
        else if (kind[i] == "") bad("column " $i ": no unit suffix and not a listed dimensionless or textual name (docs/csv_columns.txt)")
        if ($i in seen) bad("column " $i " appears twice")
        seen[$i] = 1
      }
      next
    }
    {
      rows++
      if (NF != ncol) { bad(NF " fields, the header has " ncol); next }
      for (i = 1; i <= NF; i++) {
        v = $i
        if (v == "" || v == "nan" || v == "inf" || v == "-inf") continue
        if (col[i] ~ /_each_/ && kind[i] != "text") { # every repeat: numbers separated by ;
          m = split(v, part, ";")
          for (q = 1; q <= m; q++)
            if (part[q] != "nan" && part[q] != "inf" && part[q] != "-inf" && part[q] !~ num) {
              bad("column " col[i] ": \"" v "\" is not a list of numbers separated by ;"); break
            }
          continue
        }
        lv = tolower(v)
        if (lv ~ /^[-+]?(nan|inf|infinity)([(].*[)])?$/) { bad("column " col[i] ": \"" v "\" (a non-finite value is spelled nan, inf or -inf)"); continue }
        if (kind[i] != "text" && v !~ num) bad("column " col[i] ": \"" v "\" is not a number (empty, a finite number, nan, inf or -inf)")
      }
    }
    END {
      if (nfiles && !hdr) { printf "%s: no header row\n", prev; nerr++ }
      if (nerr) exit 1
      printf "csv_convention: %d files, %d rows: ok\n", nfiles, rows
    }' "$@"
}

self_test() {
  T=$(mktemp -d "${TMPDIR:-/tmp}/cbcsv.XXXXXX") || exit 1
  fail=0
  good='# git_revision: test\n# quick: 1\nscene,k_n_per_m,dt_s,wall_ms,status,step_status,rel_grad,iters,note\n'
  good=$good'a,1e4,0.033333333333333333,1.5,ok,max_iters,0.001,3,two words\n'
  good=$good'b,-0,5e-324,,diverged,ok,nan,,x\n'
  good=$good'c,.5,1.7976931348623157e+308,inf,unstable,ok,-inf,0,\n'
  printf "$good" > "$T/good.csv"
  if ! check "$T/good.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: a good CSV is rejected:"; cat "$T/out"; fail=1; fi
  # bad NAME EXPECTED LINE...: a CSV made of the good header and these lines must fail with EXPECTED in the message
  bad() {
    name=$1 want=$2; shift 2
    { printf '# quick: 1\nscene,k_n_per_m,dt_s,wall_ms,status,step_status,rel_grad,iters,note\n'; printf '%s\n' "$@"; } > "$T/$name.csv"
    if check "$T/$name.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: $name.csv passes"; fail=1
    elif ! grep -Fq -- "$want" "$T/out"; then echo "csv_convention: FAIL: $name.csv: no '$want' in:"; cat "$T/out"; fail=1; fi
  }
  bad minus_nan '"-nan"' 'a,1,-nan,1,ok,ok,1,1,'
  bad cap_nan '"NaN"' 'a,1,0.1,1,ok,ok,NaN,1,'
  bad cap_inf '"Inf"' 'a,1,0.1,Inf,ok,ok,1,1,'
  bad infinity '"infinity"' 'a,1,0.1,1,ok,ok,infinity,1,'
  bad plus_inf '"+inf"' 'a,1,0.1,1,ok,ok,+inf,1,'
  bad nan_in_text '"-nan"' 'a,1,0.1,1,-nan,ok,1,1,'
  bad word_in_number '"fast" is not a number' 'a,1,0.1,fast,ok,ok,1,1,'
  bad hex '"0x10" is not a number' 'a,1,0.1,1,ok,ok,1,0x10,'
  bad fields '10 fields, the header has 9' 'a,1,0.1,1,ok,ok,1,1,,'
  bad late_comment 'a # line after the header row' 'a,1,0.1,1,ok,ok,1,1,' '# late: 1'
  bad empty_line 'an empty line' 'a,1,0.1,1,ok,ok,1,1,' ''
  for h in 'scene,k,status' 'scene,dt,status' 'scene,mu_max,status' 'scene,grad_norm,status' 'scene,wall_ms_1e6,status'; do
    printf '# quick: 1\n%s\na,1,ok\n' "$h" > "$T/bare.csv"
    c=$(printf '%s' "$h" | cut -d, -f2)
    if check "$T/bare.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: bare column $c passes"; fail=1
    elif ! grep -Fq "column $c: no unit suffix" "$T/out"; then echo "csv_convention: FAIL: bare column $c:"; cat "$T/out"; fail=1; fi
  done
  printf '# quick: 1\nscene,Wall_MS\na,1\n' > "$T/case.csv"
  if check "$T/case.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: a non-snake_case column passes"; fail=1; fi
  printf '# quick: 1\nscene,scene\na,b\n' > "$T/dup.csv"
  if check "$T/dup.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: a repeated column passes"; fail=1; fi
  printf '# quick: 1\nscene,wall_each_ms\na,1.5;2;nan\nb,\nc,3\n' > "$T/each.csv"
  if ! check "$T/each.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: a list of repeats is rejected:"; cat "$T/out"; fail=1; fi
  printf '# quick: 1\nscene,wall_each_ms\na,1.5;fast\n' > "$T/each_bad.csv"
  if check "$T/each_bad.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: a list of repeats with a word passes"; fail=1; fi
  printf '# quick: 1\nscene,wall_ms\na,1.5;2\n' > "$T/list_bad.csv"
  if check "$T/list_bad.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: a list outside an _each_ column passes"; fail=1; fi
  printf '# only provenance\n' > "$T/nohdr.csv"
  if check "$T/nohdr.csv" > "$T/out" 2>&1; then echo "csv_convention: FAIL: a CSV without a header passes"; fail=1; fi
  rm -rf "$T"
  [ $fail = 0 ] && echo "csv_convention: self-test ok (good CSVs pass, 21 bad ones fail)"
  return $fail
}

experiments() { # the experiment programs, as the Makefile finds them
  for m in "$root"/experiments/*/main.c; do basename "$(dirname "$m")"; done
}

# results_csvs DIR: the experiments' CSVs in DIR, one a line
results_csvs() {
  for x in $(experiments); do
    for f in "$1/$x.csv" "$1/$x"_*.csv; do [ -f "$f" ] && echo "$f"; done
  done
  for f in "$1"/movies/*/*.csv; do [ -f "$f" ] && echo "$f"; done
}

mode=--quick
case ${1:-} in
--self-test) self_test; exit $? ;;
--results)
  dir=${2:?usage: tests/csv_convention.sh --results DIR}
  # shellcheck disable=SC2046 # the file names have no blanks (results/<name>.csv)
  set -- $(results_csvs "$dir")
  [ $# -gt 0 ] || { echo "csv_convention: no experiment CSV in $dir"; exit 1; }
  check "$@"; exit $? ;;
--runs) runs=${2:?usage: tests/csv_convention.sh --runs DIR} ;;
--quick | --smoke | '') mode=${1:---quick}; runs= ;;
*) check "$@"; exit $? ;;
esac

# the self-test, then the CSVs of every experiment (in DIR with --runs, else
# fresh ones: --quick or --smoke) and of simulate
self_test || exit 1
T=$(mktemp -d "${TMPDIR:-/tmp}/cbcsvrun.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
cd "$root" || exit 1
if [ -z "$runs" ]; then
  runs=$T/exp
  BUILD=$B tests/experiments.sh "$mode" "$runs" >/dev/null || exit 1
fi
# simulate: an implicit run and an explicit one that blows up (diverged rows)
"$B/simulate" configs/hanging.ini --steps 5 --csv "$T/simulate_implicit.csv" --obj "$T/s1.obj" --quiet >/dev/null 2>"$T/sim.err" ||
  { echo "csv_convention: simulate failed:"; cat "$T/sim.err"; exit 1; }
"$B/simulate" configs/hanging.ini --set integrator.method=explicit --set integrator.dt=0.012 --steps 40 \
  --csv "$T/simulate_explicit.csv" --obj "$T/s2.obj" --quiet >/dev/null 2>"$T/sim.err"
[ -s "$T/simulate_explicit.csv" ] || { echo "csv_convention: simulate (explicit) wrote no CSV:"; cat "$T/sim.err"; exit 1; }
# shellcheck disable=SC2046
set -- $(results_csvs "$runs")
[ $# -gt 0 ] || { echo "csv_convention: no experiment CSV in $runs"; exit 1; }
check "$@" "$T"/simulate_*.csv
