#!/bin/sh
# make fuzz: runs every libFuzzer harness build/fuzz/fuzz_<name> for
# FUZZ_SECONDS seconds on a copy of its seed corpus (fuzz/corpus/<kind>/),
# with AddressSanitizer (leaks included) and UndefinedBehaviorSanitizer.
# Fails on any crash, leak, timeout (FUZZ_TIMEOUT s per input) or
# out-of-memory (FUZZ_RSS_MB), and unless the harnesses together ran at
# least FUZZ_MIN_RUNS executions. Crashing inputs are kept in build/fuzz/artifacts/.
set -u
B=${BUILD:-build/fuzz}
SECONDS_EACH=${FUZZ_SECONDS:-60}
MIN_RUNS=${FUZZ_MIN_RUNS:-1000000}
TIMEOUT=${FUZZ_TIMEOUT:-10}
RSS=${FUZZ_RSS_MB:-2048}
# the harnesses write each input to a file under TMPDIR: tmpfs is ~10x faster than disk
if [ -z "${FUZZ_TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then FUZZ_TMPDIR=/dev/shm; fi
export TMPDIR=${FUZZ_TMPDIR:-${TMPDIR:-/tmp}}
mkdir -p "$B/artifacts"
total=0 fail=0
for h in "$B"/fuzz_*; do
  [ -x "$h" ] || continue
  name=$(basename "$h")
  case $name in fuzz_config) kind=config ;; fuzz_report) kind=csv ;; *) kind=obj ;; esac
  work=$B/corpus/$name
  mkdir -p "$work"
  cp fuzz/corpus/$kind/* "$work/" 2>/dev/null
  log=$B/$name.log
  echo "fuzz: $name for ${SECONDS_EACH} s (corpus fuzz/corpus/$kind, log $log)"
  CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$h" -max_total_time="$SECONDS_EACH" -timeout="$TIMEOUT" -rss_limit_mb="$RSS" -max_len=4096 \
    -artifact_prefix="$B/artifacts/$name-" -print_final_stats=1 "$work" > "$log" 2>&1
  rc=$?
  runs=$(sed -n 's/^Done \([0-9]*\) runs.*/\1/p' "$log" | tail -n 1)
  [ -n "$runs" ] || runs=$(sed -n 's/^stat::number_of_executed_units: *\([0-9]*\).*/\1/p' "$log" | tail -n 1)
  [ -n "$runs" ] || runs=0
  total=$((total + runs))
  if [ $rc -ne 0 ]; then
    echo "fuzz: $name FAILED (exit $rc) after $runs executions:"; grep -E 'ERROR|SUMMARY|Test unit written' "$log" | head -n 10
    fail=1
  else
    echo "fuzz: $name: $runs executions, no crash, leak, timeout or out-of-memory"
  fi
done
if [ $total -lt "$MIN_RUNS" ]; then echo "fuzz: only $total executions in total (at least $MIN_RUNS wanted)"; fail=1; fi
[ $fail = 0 ] && echo "fuzz: ok, $total executions in total"
exit $fail
