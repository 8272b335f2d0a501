#!/bin/sh
# The CPU lock (lib/io/experiment.c): an untimed experiment waits while a
# timed one runs, a timed one waits while any other runs, and each CSV says
# which lock it held. The lock file is a temporary one (CB_CPU_LOCK).
set -u
B=${BUILD:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/cblock.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
L=$T/cpu.lock
fail=0 n=0
ok() { n=$((n + 1)); if ! eval "$2"; then echo "lock: FAIL: $1"; fail=1; fi; }
now() { date +%s.%N; }

# 1. an untimed experiment (topology) waits for an exclusive holder
flock -x "$L" sleep 2 &
holder=$!
sleep 0.3
t0=$(now)
CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 "$B/topology" --smoke --out "$T/t.csv" >/dev/null 2>"$T/t.err"
t1=$(now)
wait $holder
ok "untimed: waited for the exclusive holder" "awk -v a=$t0 -v b=$t1 'BEGIN { exit !(b - a >= 1.2) }'"
ok "untimed: said it was waiting" "grep -q 'waiting for a timed experiment to finish' '$T/t.err'"
ok "untimed: its CSV records the shared lock" "grep -q '^# cpu_lock: shared' '$T/t.csv'"

# 2. untimed experiments share: no wait beside another shared holder
flock -s "$L" sleep 2 &
holder=$!
sleep 0.3
t0=$(now)
CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 "$B/topology" --smoke --out "$T/t2.csv" >/dev/null 2>"$T/t2.err"
t1=$(now)
ok "untimed: no wait beside a shared holder" "awk -v a=$t0 -v b=$t1 'BEGIN { exit !(b - a < 1.2) }'"
ok "untimed: no waiting message" "! grep -q waiting '$T/t2.err'"

wait $holder
# 3. a timed experiment (definiteness) waits for a shared holder, then records exclusive
flock -s "$L" sleep 2 &
holder=$!
sleep 0.3
env -u CB_QUIET CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/definiteness" --smoke --out "$T/d.csv" >/dev/null 2>"$T/d.err"
wait $holder
ok "timed: said it was waiting for the others" "grep -q 'waiting for other experiments to finish' '$T/d.err'"
ok "timed: its CSV records the exclusive lock" "grep -q '^# cpu_lock: exclusive' '$T/d.csv'"
[ $fail = 0 ] && echo "lock: ok ($n checks)"
exit $fail
