#!/bin/sh
# scripts/parallel-run.sh under GNU parallel on this machine (make check-all):
# topology --quick and definiteness --smoke as 3 shards, merged, equal a
# one-process run's CSVs apart from the date, command and timing columns
# (tests/determinism.sh's comparison); then a run interrupted (its process
# group killed after the first shard finished, one job at a time with
# parallel's --delay so that the others are still to come) that, run again,
# reruns only the shards that did not finish and gives the same merged CSVs;
# and a failed shard (a file where its folder goes), reported with its log,
# that the same command reruns once the cause is gone.
set -u
B=${BUILD:-build}
fail() { echo "parallel: FAIL: $*"; exit 1; }
command -v parallel >/dev/null 2>&1 || fail "GNU parallel not found (scripts/deps.sh parallel)"
for x in topology definiteness; do [ -x "$B/$x" ] || fail "$B/$x not built"; done
T=$(mktemp -d "${TMPDIR:-/tmp}/cbparallel.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
trap 'exit 1' INT TERM HUP
ref() { # experiment mode: the one-process run into $T/ref
  mkdir -p "$T/ref"
  [ -f "$T/ref/$1.csv" ] || CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/$1" $2 --out "$T/ref/$1.csv" >/dev/null 2>"$T/err" ||
    { cat "$T/err"; fail "$1 $2 (one process) failed"; }
}
same() { # experiment mode dir what
  out=$(BUILD=$B tests/determinism.sh $2 "$1" "$T/ref" "$3") || { echo "$out"; fail "$4: merged CSVs differ from the one-process run's"; }
}
for spec in topology:--quick definiteness:--smoke; do
  x=${spec%%:*} mode=${spec#*:}
  ref $x $mode
  BUILD=$B scripts/parallel-run.sh --dir "$T/w-$x" $mode $x 3 -j2 >"$T/out" 2>&1 || { cat "$T/out"; fail "parallel-run.sh $mode $x 3 failed"; }
  grep -q "merged 3 shards" "$T/out" || { cat "$T/out"; fail "$x: no merge"; }
  [ "$(awk 'NR > 1 && $7 == 0' "$T/w-$x/joblog" | wc -l)" = 3 ] || fail "$x: the joblog lacks 3 successful jobs"
  for i in 1 2 3; do [ -f "$T/w-$x/logs/$x-shard-$i.log" ] || fail "$x: no log of shard $i"; done
  same $x $mode "$T/w-$x" "$x $mode"
  echo "parallel: $x $mode as 3 shards under GNU parallel, merged: the one-process run's CSVs (apart from date and timing columns)"
done

# interrupted: one job at a time, 3 s between starts; killed (the script, parallel and its jobs) once shard 1 is in the joblog
x=definiteness mode=--smoke
w=$T/w-int
killtree() { # $1 and its descendants (by parent pid): the interruption
  for c in $(ps -o pid= --ppid "$1" 2>/dev/null); do killtree "$c"; done
  kill -KILL "$1" 2>/dev/null
}
BUILD=$B scripts/parallel-run.sh --dir "$w" $mode $x 3 -j1 --delay 3 >"$T/int.out" 2>&1 &
pg=$!
k=0
until [ "$(awk 'NR > 1' "$w/joblog" 2>/dev/null | wc -l)" -ge 1 ]; do
  k=$((k + 1)); [ $k -le 600 ] || { killtree $pg; cat "$T/int.out"; fail "interrupted run: shard 1 did not finish in 120 s"; }
  sleep 0.2
done
killtree $pg
wait $pg 2>/dev/null
done_before=$(awk 'NR > 1 && $7 == 0' "$w/joblog" | wc -l)
[ "$done_before" -lt 3 ] || fail "interrupted run: all 3 shards finished before the interruption (nothing to resume)"
[ ! -f "$w/$x.csv" ] || fail "interrupted run: merged although interrupted"
BUILD=$B scripts/parallel-run.sh --dir "$w" $mode $x 3 -j1 >"$T/out" 2>&1 || { cat "$T/out"; fail "resumed run failed"; }
grep -q "merged 3 shards" "$T/out" || { cat "$T/out"; fail "resumed run: no merge"; }
ran=$(awk 'NR > 1' "$w/joblog" | wc -l)
[ "$(awk 'NR > 1 && $1 == 1 && $7 == 0' "$w/joblog" | wc -l)" = 1 ] || fail "resumed run: shard 1, finished before the interruption, ran again"
same $x $mode "$w" "interrupted and resumed run"
echo "parallel: an interrupted run ($done_before of 3 shards done) resumed ($ran joblog entries in all; shard 1 not rerun): the one-process run's CSVs"

# a failed shard: reported with its log; the same command reruns it alone, then merges
w=$T/w-fail
mkdir -p "$w"
: >"$w/shard-2"
BUILD=$B scripts/parallel-run.sh --dir "$w" $mode $x 3 -j2 >"$T/out" 2>&1 && { cat "$T/out"; fail "a run with a failing shard succeeded"; }
grep -q "shards without their output: 2 " "$T/out" || { cat "$T/out"; fail "the failing shard 2 is not reported"; }
[ ! -f "$w/$x.csv" ] || fail "a run with a failed shard merged"
rm -f "$w/shard-2"
BUILD=$B scripts/parallel-run.sh --dir "$w" $mode $x 3 -j2 >"$T/out" 2>&1 || { cat "$T/out"; fail "the rerun of the failed shard failed"; }
[ "$(awk 'NR > 1 && $1 == 2' "$w/joblog" | wc -l)" = 2 ] || fail "rerun: shard 2 not run twice in the joblog"
[ "$(awk 'NR > 1 && $1 == 1' "$w/joblog" | wc -l)" = 1 ] || fail "rerun: shard 1 ran again"
same $x $mode "$w" "rerun of a failed shard"
echo "parallel: a failed shard (reported with its log) rerun alone by the same command: the one-process run's CSVs"
# the whole run: every experiment's unsharded --smoke run and its report (the reference verdicts)
allref() {
  mkdir -p "$T/allref"
  for x in $(ls experiments); do
    [ -x "$B/$x" ] || fail "$B/$x not built"
    CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/$x" --smoke --out "$T/allref/$x.csv" >/dev/null 2>"$T/err" || { cat "$T/err"; fail "$x --smoke failed"; }
  done
  "$B/report" --results "$T/allref" --plots "$T/allref/plots" --out "$T/allref/REPORT.md" >/dev/null 2>"$T/err" || { cat "$T/err"; fail "report on the unsharded run failed"; }
}
allref
CB_QUIET=1 BUILD=$B scripts/parallel-run.sh --dir "$T/w-all" --out "$T/all-out" --smoke all 3 -j2 >"$T/out" 2>&1 || { cat "$T/out"; fail "parallel-run.sh --smoke all 3 failed"; }
[ "$(awk 'NR > 1 && $7 == 0' "$T/w-all/joblog" | wc -l)" = 3 ] || fail "all: the joblog lacks 3 successful groups"
out=$(tests/verdicts.sh "$T/allref/REPORT.md" "$T/all-out/REPORT.md") || { echo "$out"; fail "all 3: the verdict table differs from the unsharded run's"; }
echo "parallel: --smoke all 3 (every experiment in 3 groups, merged, plotted, reported): $out"
echo "parallel: all passed"
