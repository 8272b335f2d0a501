#!/bin/sh
# Every experiment once, --smoke (make check) or --quick (make check-all), its
# CSVs into DIR/<name>.csv (and DIR/<name>_*.csv): the runs that the checks
# after it read (tests/csv_convention.sh --runs DIR, tests/report.sh with
# SMOKE_DIR, tests/shard.sh and tests/determinism.sh against DIR), so that
# each experiment runs once for all of them. Prints each run's wall time.
#   tests/experiments.sh --smoke|--quick DIR [EXPERIMENT...]
# Run from the repository root (BUILD=<dir>, default build).
set -u
B=${BUILD:-build}
mode=${1:-}
dir=${2:-}
case $mode in --smoke | --quick) ;; *) dir= ;; esac
[ -n "$dir" ] || { echo "usage: tests/experiments.sh --smoke|--quick DIR [EXPERIMENT...]" >&2; exit 2; }
shift 2
[ $# -gt 0 ] || for m in experiments/*/main.c; do set -- "$@" "$(basename "$(dirname "$m")")"; done
rm -rf "$dir" && mkdir -p "$dir" || exit 1
total0=$(date +%s.%N)
for x in "$@"; do
  t0=$(date +%s.%N)
  CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/$x" "$mode" --out "$dir/$x.csv" >/dev/null 2>"$dir/$x.err" ||
    { echo "experiments: $x $mode failed:"; cat "$dir/$x.err"; exit 1; }
  t1=$(date +%s.%N)
  rm -f "$dir/$x.err"
  awk -v a="$t0" -v b="$t1" -v x="$x" -v m="$mode" 'BEGIN { printf "experiments: %s %s %.1f s\n", x, m, b - a }'
done
awk -v a="$total0" -v b="$(date +%s.%N)" -v n=$# -v m="$mode" -v d="$dir" \
  'BEGIN { printf "experiments: %d experiments %s in %.1f s, CSVs in %s\n", n, m, b - a, d }'
