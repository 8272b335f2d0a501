#!/bin/sh
# make compare: this run's verdicts (results/, or the folder given) against the
# committed reference run of the nearest CPU, results/reference/<cpu>/: the
# folder named after this CPU's model (as `# cpu:` in the CSVs, with every
# character other than a letter, digit, '.', '-' or '_' turned into '_'), else
# the one whose name shares the most words with it. Prints build/report
# --compare's table; exits 1 when a verdict differs outside the spreads, 2
# when there is nothing to compare with.
#   scripts/compare.sh [RESULTS_DIR]     (REFERENCE_ROOT=... for another root)
set -u
B=${BUILD:-build}
ours=${1:-results}
root=${REFERENCE_ROOT:-results/reference}
[ -d "$ours" ] || { echo "compare: no $ours/: run make experiments first" >&2; exit 2; }
cpu=$(sed -n 's/^model name[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo 2>/dev/null | head -n 1)
key=$(printf '%s' "$cpu" | tr -c 'A-Za-z0-9._-' '_')
best="" bestscore=-1
for d in "$root"/*/; do
  [ -d "$d" ] || continue
  name=$(basename "$d")
  if [ "$name" = "$key" ]; then best=$d; bestscore=1000; break; fi
  score=0
  for w in $(printf '%s' "$key" | tr '_' ' '); do
    case "_${name}_" in *"_${w}_"*) score=$((score + 1)) ;; esac
  done
  if [ $score -gt $bestscore ]; then best=$d bestscore=$score; fi
done
if [ -z "$best" ]; then
  echo "compare: no reference run under $root/ (a full make experiments, committed as $root/<cpu>/, is one)" >&2
  exit 2
fi
best=${best%/}
echo "compare: this CPU: ${cpu:-unknown}; reference: $best$([ $bestscore = 1000 ] || echo ' (another CPU: timings may differ)')"
exec "$B/report" --compare "$best" --results "$ours"
