#!/bin/sh
# The whole run (every experiment) as N groups of units, the steps that
# scripts/slurm-submit.sh all N and scripts/parallel-run.sh all N run:
#   scripts/all-run.sh plan  DIR MODE N   the plan, DIR/plan (scripts/lib/all-plan.py):
#                                         every experiment cut into units (its own
#                                         --shard j/k; bending whole), the units balanced
#                                         into N groups by their hints times the
#                                         experiment's recorded wall time, or with
#                                         CB_ALL_TIMES=DIR (a recorded run of the same
#                                         mode) by its recorded cell times
#   scripts/all-run.sh group DIR MODE I   runs group I's units one after another:
#                                         DIR/<experiment>/shard-j/<experiment>.csv, or
#                                         DIR/<experiment>/whole/<experiment>.csv
#   scripts/all-run.sh merge DIR OUT      merges every experiment into OUT (the
#                                         results folder): scripts/merge-shards.sh's
#                                         checks per experiment (one run, every cell
#                                         once), then one git revision across all the
#                                         CSVs; then the plots (OUT/plots) and the report
#                                         (OUT/REPORT.md)
# MODE is --quick, --smoke or - (a full run). BUILD (default build) is the
# build folder. Each unit runs with its own CPU lock (DIR/locks/group-I.lock).
set -eu
die() { echo "all-run: $*" >&2; exit 1; }
repo=$(cd "$(dirname "$0")/.." && pwd)
cd "$repo"
B=${BUILD:-build}
case $B in /*) ;; *) B=$repo/$B ;; esac
[ $# -ge 3 ] || die "usage: $0 plan DIR MODE N | group DIR MODE I | merge DIR OUT"
step=$1 dir=$2
case $dir in /*) ;; *) dir=$repo/$dir ;; esac
case $step in
plan)
  mode=$3 n=${4:-}
  case $n in '' | *[!0-9]* | 0*) die "N '$n': expected a positive whole number" ;; esac
  [ "$mode" != - ] || mode=""
  mkdir -p "$dir"
  # CB_ALL_TIMES=DIR: a recorded run of the same mode; its cell times balance the groups (all-plan.py --times)
  set -- "$B" "$mode" "$n" docs/running.md
  [ -z "${CB_ALL_TIMES:-}" ] || set -- "$@" --times "$CB_ALL_TIMES"
  python3 scripts/lib/all-plan.py "$@" > "$dir/plan.tmp.$$" || { rm -f "$dir/plan.tmp.$$"; die "no plan (above)"; }
  mv "$dir/plan.tmp.$$" "$dir/plan"
  printf '%s\n' "${mode:--}" > "$dir/mode"
  ;;
group)
  mode=$3 i=${4:-}
  [ "$mode" != - ] || mode=""
  [ -f "$dir/plan" ] || die "$dir/plan: missing (all-run.sh plan first)"
  mkdir -p "$dir/locks"
  export CB_CPU_LOCK="$dir/locks/group-$i.lock"
  awk -v i="$i" '$1 == i { print $2, $3, $4 }' "$dir/plan" | while read -r x j k; do
    t0=$(date +%s.%N)
    if [ "$j" = 0 ]; then
      mkdir -p "$dir/$x/whole"
      echo "all-run: group $i: $x (whole)" >&2
      # shellcheck disable=SC2086 # mode is empty or one word
      "$B/$x" $mode --out "$dir/$x/whole/$x.csv" || exit 1
    else
      mkdir -p "$dir/$x/shard-$j"
      echo "all-run: group $i: $x --shard $j/$k" >&2
      # shellcheck disable=SC2086
      "$B/$x" $mode --shard "$j/$k" --out "$dir/$x/shard-$j/$x.csv" || exit 1
    fi
    # the unit's wall seconds (scripts/makespan.py: a whole unit has no per-cell times)
    u=whole; [ "$j" = 0 ] || u=shard-$j
    awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f\n", b - a }' > "$dir/$x/$u/seconds"
  done
  ;;
merge)
  out=$3
  case $out in /*) ;; *) out=$repo/$out ;; esac
  [ -f "$dir/plan" ] || die "$dir/plan: missing"
  mkdir -p "$out"
  for x in $(awk '{ print $2 }' "$dir/plan" | sort -u); do
    k=$(awk -v x="$x" '$2 == x { print $4; exit }' "$dir/plan")
    if [ "$k" = 0 ]; then
      [ -f "$dir/$x/whole/$x.csv" ] || die "$dir/$x/whole/$x.csv: missing (its unit failed?)"
      for f in "$dir/$x/whole/$x".csv "$dir/$x/whole/$x"_*; do [ -f "$f" ] && cp "$f" "$out/" ; done
    else
      shards=$(i=1; while [ "$i" -le "$k" ]; do printf '%s\n' "$dir/$x/shard-$i/$x.csv"; i=$((i + 1)); done)
      # shellcheck disable=SC2086 # the paths hold no spaces (DIR is checked below)
      scripts/merge-shards.sh "$out/$x.csv" $shards || die "$x: the merge failed (above)"
    fi
    echo "all-run: $x merged into $out/$x.csv" >&2
  done
  # one revision and build across the whole run
  revs=$(for f in "$out"/*.csv; do sed -n 's/^# git_revision: //p' "$f" | head -n 1; done | sort -u)
  [ "$(printf '%s\n' "$revs" | grep -c .)" = 1 ] || die "the experiments' CSVs come from more than one git revision: $(echo $revs)"
  RESULTS=$out PLOTS_OUT=$out/plots scripts/plots.sh || die "plots failed (above)"
  "$B/report" --results "$out" --plots "$out/plots" --out "$out/REPORT.md" || die "report failed"
  echo "all-run: the whole run merged into $out, its report $out/REPORT.md"
  ;;
*) die "unknown step '$step'" ;;
esac
