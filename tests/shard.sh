#!/bin/sh
# --shard I/N: running an experiment's cells as N shards and merging the
# shards' CSVs with scripts/merge-shards.sh gives the unsharded CSVs (main and
# side tables), apart from the date, command and timing columns that
# tests/determinism.sh strips. Usage: tests/shard.sh [--quick|--smoke] EXPERIMENT N
# (the runs are --quick ones, or --smoke ones with --smoke). With
# UNSHARDED_DIR=<dir> holding an unsharded run's CSVs of this build (make
# check's smoke runs, make check-all's quick runs), the merge is compared
# with those instead of a new unsharded run.
set -u
B=${BUILD:-build}
mode=--quick
case ${1:-} in --smoke | --quick) mode=$1; shift ;; esac
exp=${1:?usage: tests/shard.sh [--quick|--smoke] EXPERIMENT N}
n=${2:?usage: tests/shard.sh [--quick|--smoke] EXPERIMENT N}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbshard.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
files=""
i=1
while [ "$i" -le "$n" ]; do
  CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/$exp" $mode --shard "$i/$n" --out "$T/s$i/$exp.csv" \
    >/dev/null 2>"$T/err" || { echo "shard: $exp --shard $i/$n failed:"; cat "$T/err"; exit 1; }
  files="$files $T/s$i/$exp.csv"
  i=$((i + 1))
done
# shellcheck disable=SC2086
scripts/merge-shards.sh "$T/merged/$exp.csv" $files || { echo "shard: merging $exp failed"; exit 1; }
out=$(BUILD=$B tests/determinism.sh $mode "$exp" "$T/merged" ${UNSHARDED_DIR:-}) || { echo "shard: $exp: merged shards differ:"; echo "$out"; exit 1; }
echo "shard: $exp $mode as $n merged shards gives the unsharded CSVs (apart from date and timing columns)"
