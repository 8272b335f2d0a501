#!/bin/sh
# The second run of every experiment, compared with the first run's CSVs in
# DIR (apart from the date, machine and timing columns): an experiment with a
# shard count in SHARDS ("name:N ...") runs as N shards merged
# (tests/shard.sh, which also shows the merge), the others whole
# (tests/determinism.sh). Either way it is the determinism check, so no
# experiment runs a third time.
#   tests/rerun.sh [-j N] --smoke|--quick DIR "SHARDS" EXPERIMENT...
# With -j N, N at a time, each with a CPU lock of its own inside a shared hold
# of the machine's (as tests/experiments.sh -j): the timing columns of these
# runs are blanked by the comparison and are not measurements.
set -u
B=${BUILD:-build}
if [ "${1:-}" = --one ]; then # --one MODE DIR SHARDS EXPERIMENT
  mode=$2 dir=$3 shards=$4 x=$5 n=
  for s in $shards; do [ "${s%%:*}" = "$x" ] && n=${s##*:}; done
  [ -n "${CB_OWN_LOCK:-}" ] && { CB_CPU_LOCK=$dir/$x.rerun.lock; export CB_CPU_LOCK; }
  if [ -n "$n" ]; then BUILD=$B UNSHARDED_DIR=$dir tests/shard.sh "$mode" "$x" "$n"
  else BUILD=$B tests/determinism.sh "$mode" "$x" "$dir"; fi || exit 255
  rm -f "$dir/$x.rerun.lock"
  exit 0
fi
jobs=1
[ "${1:-}" = -j ] && { jobs=${2:?usage: -j N}; shift 2; }
[ $# -ge 4 ] || { echo "usage: tests/rerun.sh [-j N] --smoke|--quick DIR \"SHARDS\" EXPERIMENT..." >&2; exit 2; }
mode=$1 dir=$2 shards=$3
shift 3
if [ "$jobs" -le 1 ]; then
  for x in "$@"; do "$0" --one "$mode" "$dir" "$shards" "$x" || exit 1; done
else
  printf '%s\n' "$@" | CB_OWN_LOCK=1 flock -s "${CB_CPU_LOCK:-/tmp/clothbench-cpu.lock}" \
    xargs -P "$jobs" -n 1 "$0" --one "$mode" "$dir" "$shards" || exit 1
fi
