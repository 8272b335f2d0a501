#!/bin/sh
# Every experiment once, --smoke (make check) or --quick (make check-all), its
# CSVs into DIR/<name>.csv (and DIR/<name>_*.csv): the runs that the checks
# after it read (tests/csv_convention.sh --runs DIR, tests/report.sh with
# SMOKE_DIR, tests/shard.sh and tests/determinism.sh against DIR), so that
# each experiment runs once for all of them. Prints each run's wall time.
#   tests/experiments.sh [-j N] --smoke|--quick DIR [EXPERIMENT...]
# With -j N, N experiments run at a time, each with a CPU lock of its own
# (DIR/<name>.lock) inside the batch's shared hold of the machine's lock
# (CB_CPU_LOCK, as lib/io/experiment.c takes it): their timing columns are then not
# measurements, which is right for the checks (they blank them) and wrong for
# anything published (make experiments runs one timed experiment at a time).
# The experiments start in the order given, so give the longest first.
# Run from the repository root (BUILD=<dir>, default build).
set -u
B=${BUILD:-build}
# --one MODE DIR EXPERIMENT: one run (what -j starts, N at a time)
if [ "${1:-}" = --one ]; then
  mode=$2 dir=$3 x=$4
  t0=$(date +%s.%N)
  [ -n "${CB_OWN_LOCK:-}" ] && { CB_CPU_LOCK=$dir/$x.lock; export CB_CPU_LOCK; }
  CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/$x" "$mode" --out "$dir/$x.csv" >/dev/null 2>"$dir/$x.err" ||
    { echo "experiments: $x $mode failed:"; cat "$dir/$x.err"; exit 255; }
  t1=$(date +%s.%N)
  rm -f "$dir/$x.err" "$dir/$x.lock"
  awk -v a="$t0" -v b="$t1" -v x="$x" -v m="$mode" 'BEGIN { printf "experiments: %s %s %.1f s\n", x, m, b - a }'
  exit 0
fi
jobs=1
[ "${1:-}" = -j ] && { jobs=${2:?usage: -j N}; shift 2; }
mode=${1:-}
dir=${2:-}
case $mode in --smoke | --quick) ;; *) dir= ;; esac
[ -n "$dir" ] || { echo "usage: tests/experiments.sh --smoke|--quick DIR [EXPERIMENT...]" >&2; exit 2; }
shift 2
[ $# -gt 0 ] || for m in experiments/*/main.c; do set -- "$@" "$(basename "$(dirname "$m")")"; done
rm -rf "$dir" && mkdir -p "$dir" || exit 1
total0=$(date +%s.%N)
if [ "$jobs" -le 1 ]; then
  for x in "$@"; do "$0" --one "$mode" "$dir" "$x" || exit 1; done
else
  # The batch holds the machine's CPU lock shared, as one untimed experiment
  # would: a timed experiment elsewhere waits for it, and it for one. xargs
  # stops at the first run that fails (exit 255).
  printf '%s\n' "$@" | CB_OWN_LOCK=1 flock -s "${CB_CPU_LOCK:-/tmp/clothbench-cpu.lock}" \
    xargs -P "$jobs" -n 1 "$0" --one "$mode" "$dir" || exit 1
fi
awk -v a="$total0" -v b="$(date +%s.%N)" -v n=$# -v m="$mode" -v d="$dir" -v j="$jobs" \
  'BEGIN { printf "experiments: %d experiments %s in %.1f s (%d at a time), CSVs in %s\n", n, m, b - a, j, d }'
