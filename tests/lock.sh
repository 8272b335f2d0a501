#!/bin/sh
# The CPU lock (lib/io/experiment.c): an untimed experiment waits while a
# timed one runs, a timed one waits while any other runs, an experiment that
# locks per cell takes the lock exclusively for its timed cells only (by sweep or, through cb_sweep.timed, by
# cell), every experiment that runs cells locks per cell, a waiting
# timed cell is not passed by newcomers, and each CSV says which lock it held. The lock file is a temporary one (CB_CPU_LOCK).
set -u
B=${BUILD:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/cblock.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
L=$T/cpu.lock
fail=0 n=0
ok() { n=$((n + 1)); if ! eval "$2"; then echo "lock: FAIL: $1"; fail=1; fi; }

# hold MODE NAME: holds the lock (flock -x or -s) until $T/NAME.stop exists,
# having written $T/NAME.held once it holds it; it writes $T/NAME.released
# just before it lets go. The checks read these files, not the clock, so a
# loaded machine cannot make them fail.
hold() {
  flock "$1" "$L" sh -c 'touch "$0.held"; while [ ! -e "$0.stop" ]; do sleep 0.05; done; touch "$0.released"' "$T/$2" &
  holder=$!
  while [ ! -e "$T/$2.held" ]; do sleep 0.05; done
}
# release NAME: tells the holder to let go
release() { touch "$T/$1.stop"; }
# release_when NAME FILE TEXT: in the background, tells the holder to let go once FILE (a waiting
# program's stderr) says TEXT, or after 300 s (then the check on TEXT fails). Not a timer: a slow
# start (a loaded machine, the sanitizers) must not release the holder before the program waits.
release_when() {
  (i=0; while ! grep -q "$3" "$2" 2>/dev/null && [ $i -lt 6000 ]; do sleep 0.05; i=$((i + 1)); done
   touch "$T/$1.stop") &
}
# wait_for FILE TEXT: until FILE says TEXT (at most 300 s)
wait_for() { i=0; while ! grep -q "$2" "$1" 2>/dev/null && [ $i -lt 6000 ]; do sleep 0.05; i=$((i + 1)); done; }

# 1. an untimed experiment (topology) waits for an exclusive holder
hold -x x
release_when x "$T/t.err" 'waiting for a timed experiment to finish'
env -u CB_QUIET CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 "$B/topology" --smoke --out "$T/t.csv" >/dev/null 2>"$T/t.err"
ok "untimed: waited for the exclusive holder" "test -e '$T/x.released'"
wait $holder
ok "untimed: said it was waiting" "grep -q 'waiting for a timed experiment to finish' '$T/t.err'"
ok "untimed: its CSV records the shared lock" "grep -q '^# cpu_lock: shared' '$T/t.csv'"

# 2. untimed experiments share: no wait beside another shared holder (which
#    lets go only once the experiment has finished)
hold -s s
CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 "$B/topology" --smoke --out "$T/t2.csv" >/dev/null 2>"$T/t2.err"
ok "untimed: no wait beside a shared holder" "test ! -e '$T/s.released'"
release s
wait $holder
ok "untimed: no waiting message" "! grep -q waiting '$T/t2.err'"

# 3. a timed experiment (bending, which does not run its work as cells) waits for a shared holder, then
#    records exclusive
hold -s d
release_when d "$T/d.err" 'waiting for other experiments to finish'
env -u CB_QUIET CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/bending" --smoke --out "$T/d.csv" >/dev/null 2>"$T/d.err"
ok "timed: waited for the shared holder" "test -e '$T/d.released'"
wait $holder
ok "timed: said it was waiting for the others" "grep -q 'waiting for other experiments to finish' '$T/d.err'"
ok "timed: its CSV records the exclusive lock" "grep -q '^# cpu_lock: exclusive' '$T/d.csv'"

# 4. an experiment that locks per cell (definiteness: its trajectory cells are timed) waits for a
#    shared holder before its timed cells, says so, and records the per-cell lock
hold -s c
release_when c "$T/c.err" 'waiting for other cells and experiments to finish: a timed cell runs alone'
env -u CB_QUIET CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/definiteness" --smoke --out "$T/c.csv" >/dev/null 2>"$T/c.err"
ok "per cell: a timed cell waited for the shared holder" "test -e '$T/c.released'"
wait $holder
ok "per cell: said a timed cell was waiting" "grep -q 'waiting for other cells and experiments to finish: a timed cell runs alone' '$T/c.err'"
ok "per cell: its CSV records the per-cell lock" "grep -q '^# cpu_lock: per cell' '$T/c.csv'"
ok "per cell: the split of its cell seconds" "grep -q '^timed_cells_s: ' '$T/c.csv.split' && grep -q '^cell_locks: 1' '$T/c.csv.split'"

# 5. the turnstile: while a timed cell waits (for a shared holder), a newcomer asking for the shared
#    lock waits behind it, rather than passing it (flock alone would let it through)
hold -s w
env -u CB_QUIET CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/definiteness" --smoke --out "$T/w.csv" >/dev/null 2>"$T/w.err" &
dpid=$!
wait_for "$T/w.err" 'a timed cell runs alone' # definiteness now waits for its first timed cell, holding the turnstile
CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 "$B/topology" --smoke --out "$T/w2.csv" >/dev/null 2>&1 &
tpid=$!
sleep 2
ok "turnstile: a shared newcomer passed a waiting timed cell" "test ! -e '$T/w2.csv'"
release w
wait $holder $dpid $tpid
ok "turnstile: both ran once the holder let go" "test -s '$T/w.csv' -a -s '$T/w2.csv'"
# 6. a sweep whose cells are of several kinds (explicit_stability's map: cb_sweep.timed per cell): its
#    explicit and Newton cells run beside a shared holder, its E2 cell waits for it, and the run records
#    seconds of both kinds
hold -s m
release_when m "$T/m.err" 'a timed cell runs alone'
env -u CB_QUIET CB_CPU_LOCK=$L OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/explicit_stability" --smoke --out "$T/m.csv" >/dev/null 2>"$T/m.err"
ok "per cell (map): the timed E2 cell waited for the shared holder" "test -e '$T/m.released'"
wait $holder
ok "per cell (map): it said a timed cell was waiting" "grep -q 'a timed cell runs alone' '$T/m.err'"
ok "per cell (map): its CSV records the per-cell lock" "grep -q '^# cpu_lock: per cell' '$T/m.csv'"
ok "per cell (map): seconds in timed and in untimed cells" "awk '/^timed_cells_s:/ { t = \$2 > 0 } /^untimed_cells_s:/ { u = \$2 > 0 } END { exit !(t && u) }' '$T/m.csv.split'"
ok "per cell (map): --list-cells marks the E2 cell timed and the explicit sweep untimed" "'$B/explicit_stability' --smoke --list-cells --out '$T/l.csv' | awk '\$3 == \"map\" { k[\$7]++ } END { exit !(k[0] >= 1 && k[1] >= 1) }'"

# 7. every experiment that runs its work as sweep cells locks per cell (cb_experiment_timed_cells), so
#    its untimed cells fill the other cores; only a program without cells (bending) locks as a whole
for f in experiments/*/main.c; do
  if grep -q 'cb_sweep_run' "$f"; then
    ok "$f: runs cells but locks the whole process (cb_experiment_timed)" "! grep -q 'cb_experiment_timed(' '$f'"
  fi
done

[ $fail = 0 ] && echo "lock: ok ($n checks)"
exit $fail
