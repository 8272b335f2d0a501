#!/bin/sh
# Re-running an experiment gives the same CSV apart from the date and the
# timing columns. Runs build/<experiment> --quick (or --smoke, given as the
# first argument) twice and compares; with a
# second argument, runs it once and compares with the CSVs of an earlier run
# kept in that folder (<experiment>.csv and <experiment>_*.csv, e.g. from
# `build/<experiment> --quick --out DIR/<experiment>.csv` at another revision);
# with a third, runs nothing and compares that folder's CSVs (the "new run",
# e.g. make check-all's quick runs) with the second's (tests/shard.sh does).
# Timing columns: names ending in _ms, or containing wall, time or speedup
# (the naming convention for every wall-clock-derived column, the spread
# columns of repeated timings included: wall_min_ms, wall_each_ms_per_s,
# step_max_ms, wall_repeats, ...; see README and lib/instruments/stats.h),
# and measured memory, names ending in _mib (the resident set depends on the
# allocator's state and the machine: J4's mem_peak_mib).
set -u
B=${BUILD:-build}
mode=--quick
case ${1:-} in --smoke | --quick) mode=$1; shift ;; esac
exp=${1:?usage: tests/determinism.sh [--quick|--smoke] EXPERIMENT [BASELINE_DIR [NEW_DIR]]}
base=${2:-}
new=${3:-}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbdet.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
strip() { # drop '# date:' and '# command:' lines; blank timing columns
  awk -F, -v OFS=, '
    /^# (date|command|git_revision|cflags|cpu|cores|cpu_lock):/ { next }
    /^#/ { print; next }
    !hdr { hdr = 1; for (i = 1; i <= NF; i++) if ($i ~ /_ms$|_mib$|wall|time|speedup/) t[i] = 1; print; next }
    { for (i in t) $i = "-"; print }' "$1"
}
runs="1 2"
if [ -n "$base" ]; then
  [ -f "$base/$exp.csv" ] || { echo "determinism: no $base/$exp.csv"; exit 1; }
  runs=1
  strip "$base/$exp.csv" > "$T/s2.csv"
  for side in "$base/$exp"_*.csv; do [ -f "$side" ] && strip "$side" > "$T/s2.$(basename "$side" | sed "s/^$exp//")"; done
fi
if [ -n "$new" ]; then # the new run is there already: link its CSVs in as run 1's
  [ -f "$new/$exp.csv" ] || { echo "determinism: no $new/$exp.csv"; exit 1; }
  for f in "$new/$exp.csv" "$new/$exp"_*.csv; do [ -f "$f" ] && cp "$f" "$T/run1$(basename "$f" | sed "s/^$exp//")"; done
fi
for k in $runs; do
  if [ -z "$new" ]; then
    CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/$exp" $mode --out "$T/run$k.csv" >/dev/null 2>"$T/err$k" ||
      { echo "determinism: $exp run $k failed:"; cat "$T/err$k"; exit 1; }
  fi
  strip "$T/run$k.csv" > "$T/s$k.csv"
  for side in "$T"/run"$k"_*.csv; do [ -f "$side" ] && strip "$side" > "$T/s$k.$(basename "$side" | sed "s/^run$k//")"; done
done
fail=0
for f in "$T"/s1*; do
  g=$T/s2${f#"$T"/s1}
  if ! cmp -s "$f" "$g"; then
    echo "determinism: $exp: $(basename "$f") differs between two runs:"; diff "$f" "$g" | head -10; fail=1
  fi
done
for g in "$T"/s2*; do
  f=$T/s1${g#"$T"/s2}
  if [ ! -f "$f" ]; then echo "determinism: $exp: $(basename "$g") is missing from the new run"; fail=1
  fi
done
if [ $fail = 0 ]; then
  if [ -n "$new" ]; then echo "determinism: $exp: the CSVs of $new are those of $base (apart from date, machine, git revision, cflags and timing columns)"
  elif [ -n "$base" ]; then echo "determinism: $exp $mode gives the CSVs of $base (apart from date, machine, git revision, cflags and timing columns)"
  else echo "determinism: $exp $mode gives identical CSV twice (apart from date and timing columns)"; fi
fi
exit $fail
