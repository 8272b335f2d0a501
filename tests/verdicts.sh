#!/bin/sh
# Compares the verdict tables of two reports (tests/parallel.sh, tests/slurm.sh:
# the whole run as groups against an unsharded run):
#   tests/verdicts.sh REPORT_A.md REPORT_B.md
# Compares every claim's row (claim, verdict) of the verdict table, except
# the claims whose section quotes timings in either report ("repeats",
# "paired", "wall time", or a verdict undecided within a timing's spread: a
# verdict decided on timings, which a loaded machine can move between any two
# runs, sharded or not); prints the claims compared and exits 1 on a
# difference, or when no claim is left to compare. Only a claim's first row
# counts (the summary table; the undecided claims' table repeats them).
set -u
[ $# = 2 ] || { echo "usage: $0 A.md B.md" >&2; exit 2; }
for r in "$1" "$2"; do [ -f "$r" ] || { echo "verdicts: $r: missing"; exit 1; }; done
timed=$(for r in "$1" "$2"; do awk '/^<a id="/ { id = $0; sub(/^<a id="/, "", id); sub(/".*/, "", id) } /repeats|paired|wall time|within the spread/ && id != "" { print id }' "$r"; done | sort -u | tr '\n' ' ')
rows() { grep '^| \[[A-Z][0-9]*\](#' "$1" | awk -F'|' '!seen[$2]++' | cut -d'|' -f2,3 | while IFS='|' read -r c v; do
  id=${c#*[}; id=${id%%]*}
  case " $timed " in *" $id "*) ;; *) echo "$id:$v" ;; esac
done; }
a=$(rows "$1") b=$(rows "$2")
[ -n "$a" ] || { echo "verdicts: no untimed claim in $1"; exit 1; }
if [ "$a" != "$b" ]; then
  echo "verdicts: the verdict tables differ (claims decided on timings left out: $timed)"
  printf '%s\n' "$a" > "${TMPDIR:-/tmp}/verdicts.$$.a"; printf '%s\n' "$b" > "${TMPDIR:-/tmp}/verdicts.$$.b"
  diff "${TMPDIR:-/tmp}/verdicts.$$.a" "${TMPDIR:-/tmp}/verdicts.$$.b"; rm -f "${TMPDIR:-/tmp}/verdicts.$$".?
  exit 1
fi
echo "verdicts: $(printf '%s\n' "$a" | wc -l) claims' verdicts agree (left out, decided on timings: $timed)"
