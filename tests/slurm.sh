#!/bin/sh
# scripts/slurm-submit.sh against a real Slurm on this machine (make check-all):
# starts munged (as the munge user), slurmctld and slurmd for one node (this
# host, CPUs=2) with a slurm.conf generated in a temporary folder, submits
# topology --quick and definiteness --smoke as 3-task arrays plus their merge
# jobs (topology with --cpus-per-task=2: its tasks run 2 threads), after a
# --dry-run that must print both scripts and write nothing; waits (bounded: SLURM_TEST_TIMEOUT seconds per job, default 300) and
# checks that the merged CSVs equal a one-process run's apart from the date,
# command and timing columns (tests/determinism.sh's comparison). Then a run
# whose task 2 fails: its log stays, the merge job never runs, and a rerun of
# the failed index (--rerun failed) merges to the same CSVs. The daemons it
# started are stopped by their pids. Needs root (the daemons, and munged run
# through runuser) and the Debian packages slurm-wlm and munge.
set -u
B=${BUILD:-build}
timeout=${SLURM_TEST_TIMEOUT:-300}
fail() { echo "slurm: FAIL: $*"; exit 1; }
[ "$(id -u)" = 0 ] || fail "needs root (it starts munged, slurmctld and slurmd)"
for c in munged slurmctld slurmd sbatch squeue scontrol runuser; do
  command -v $c >/dev/null 2>&1 || [ -x /usr/sbin/$c ] || fail "$c not found (scripts/deps.sh slurm-wlm munge)"
done
id munge >/dev/null 2>&1 || fail "no munge user (the munge package)"
[ -r /etc/munge/munge.key ] || fail "no /etc/munge/munge.key (the munge package creates it)"
for x in topology definiteness; do [ -x "$B/$x" ] || fail "$B/$x not built"; done
PATH=$PATH:/usr/sbin
T=$(mktemp -d "${TMPDIR:-/tmp}/cbslurm.XXXXXX") || exit 1
chmod 755 "$T"
pids="" mpid=""
stop() {
  if [ -n "${SLURM_CONF:-}" ] && [ -f "$SLURM_CONF" ]; then
    ids=$(squeue -h -o %i 2>/dev/null) && [ -z "$ids" ] || scancel $ids 2>/dev/null
  fi
  for p in $pids; do kill "$p" 2>/dev/null; done # slurmd and slurmctld
  [ -f "$T/munge/munged.pid" ] && kill "$(cat "$T/munge/munged.pid")" 2>/dev/null # munged (runuser then exits)
  for p in $pids $mpid; do
    k=0
    while kill -0 "$p" 2>/dev/null && [ $k -lt 50 ]; do sleep 0.2; k=$((k + 1)); done
    kill -9 "$p" 2>/dev/null
  done
  rm -rf "$T"
}
trap stop EXIT
trap 'exit 1' INT TERM HUP
# munged, as the munge user, on a socket of its own
mkdir -p "$T/munge" "$T/state" "$T/spool"
chown munge:munge "$T/munge" && chmod 711 "$T/munge"
runuser -u munge -- munged -F --socket="$T/munge/socket" --pid-file="$T/munge/munged.pid" --log-file="$T/munge/munged.log" \
  --seed-file="$T/munge/seed" --key-file=/etc/munge/munge.key >"$T/munged.out" 2>&1 &
mpid=$!
k=0
until [ -S "$T/munge/socket" ]; do
  k=$((k + 1)); [ $k -le 50 ] || { cat "$T/munged.out"; fail "munged did not start"; }
  sleep 0.2
done
# free ports for slurmctld and slurmd
port() {
  p=$(( 20000 + ($$ * 7 + $1 * 13) % 30000 ))
  while ss -ltnH 2>/dev/null | awk '{print $4}' | grep -q ":$p\$"; do p=$((p + 1)); done
  echo $p
}
cport=$(port 1)
dport=$(port 2)
[ "$dport" != "$cport" ] || dport=$((cport + 1))
host=$(hostname -s)
cat >"$T/slurm.conf" <<EOF
ClusterName=cbtest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$cport
SlurmdPort=$dport
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge/socket
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MailProg=/bin/true
NodeName=$host CPUs=2 State=UNKNOWN
PartitionName=cbtest Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$T/slurm.conf"
slurmctld -D -f "$SLURM_CONF" >"$T/slurmctld.out" 2>&1 &
pids="$pids $!"
slurmd -D -f "$SLURM_CONF" >"$T/slurmd.out" 2>&1 &
pids="$pids $!"
k=0
until sinfo -h -o %T 2>/dev/null | grep -q idle; do
  k=$((k + 1))
  [ $k -le 150 ] || { tail -5 "$T/slurmctld.log" "$T/slurmd.log" "$T/slurmctld.out" "$T/slurmd.out"; fail "the node did not come up idle in 30 s"; }
  sleep 0.2
done
echo "slurm: slurmctld (port $cport) and slurmd (port $dport) up, node $host idle"

# waits for job $1 to end; prints its state
wait_job() {
  k=0
  while :; do
    s=$(scontrol show job "$1" -o 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort -u | tr '\n' ' ')
    case $s in *PENDING* | *RUNNING* | *CONFIGURING* | *COMPLETING* | "") ;; *) echo "$s"; return ;; esac
    case $(scontrol show job "$1" -o 2>/dev/null) in *DependencyNeverSatisfied*) echo "NEVER"; return ;; esac
    k=$((k + 1))
    [ $k -le $((timeout * 2)) ] || { echo "TIMEOUT"; return; }
    sleep 0.5
  done
}
submit() { # dir mode experiment [cpus per task]: sets a and m, the array and merge job ids
  BUILD=$B scripts/slurm-submit.sh --dir "$1" "$2" "$3" 3 -- --cpus-per-task="${4:-1}" >"$T/submit.out" 2>&1 || { cat "$T/submit.out"; fail "slurm-submit.sh $2 $3 3 failed"; }
  a=$(sed -n 's/^array job \([0-9]*\).*/\1/p' "$T/submit.out")
  m=$(sed -n 's/^merge job \([0-9]*\).*/\1/p' "$T/submit.out")
  [ -n "$a" ] && [ -n "$m" ] || { cat "$T/submit.out"; fail "slurm-submit.sh printed no job ids"; }
}
show_logs() { for f in "$1"/logs/*.log; do echo "--- $f"; tail -5 "$f"; done; }

# --dry-run: both scripts and the sbatch commands printed, nothing written or submitted
BUILD=$B scripts/slurm-submit.sh --dry-run --dir "$T/dry" --quick topology 3 -- --cpus-per-task=2 >"$T/dry.out" 2>&1 || { cat "$T/dry.out"; fail "--dry-run failed"; }
grep -q '^#SBATCH --array=1-3$' "$T/dry.out" && grep -q 'dependency=afterok:<array job> --cpus-per-task=2' "$T/dry.out" &&
  grep -q 'OPENBLAS_NUM_THREADS=$t OMP_NUM_THREADS=$t' "$T/dry.out" && grep -q 'scripts/merge-shards.sh' "$T/dry.out" ||
  { cat "$T/dry.out"; fail "--dry-run: not the array script (threads from --cpus-per-task), the merge script and the sbatch lines"; }
[ ! -e "$T/dry" ] || fail "--dry-run wrote $T/dry"

# topology with 2 CPUs per task (so 2 threads: the one-process run gets 2 too), definiteness with 1
for spec in topology:--quick:2 definiteness:--smoke:1; do
  x=${spec%%:*} rest=${spec#*:}
  mode=${rest%%:*} cpus=${rest#*:}
  mkdir -p "$T/ref"
  CB_QUIET=1 OPENBLAS_NUM_THREADS=$cpus OMP_NUM_THREADS=$cpus "$B/$x" $mode --out "$T/ref/$x.csv" >/dev/null 2>"$T/err" ||
    { cat "$T/err"; fail "$x $mode (one process) failed"; }
  submit "$T/w-$x" "$mode" "$x" "$cpus"
  s=$(wait_job "$m")
  [ "$s" = "COMPLETED " ] || { show_logs "$T/w-$x"; fail "$x: merge job $m ended $s (array job $a: $(wait_job "$a"))"; }
  [ "$(wait_job "$a")" = "COMPLETED " ] || fail "$x: array job $a did not complete"
  n=$(ls "$T/w-$x/logs/$x-${a}"_*.log 2>/dev/null | wc -l)
  [ "$n" = 3 ] || fail "$x: $n task logs for array job $a, expected 3"
  grep -q ", $cpus thread(s)," "$T/w-$x/logs/$x-${a}_1.log" || { cat "$T/w-$x/logs/$x-${a}_1.log"; fail "$x: task 1 did not run with $cpus threads (--cpus-per-task=$cpus)"; }
  grep -q "merged 3 shards" "$T/w-$x/logs/$x-merge-$m.log" || fail "$x: the merge log says no merge"
  out=$(BUILD=$B tests/determinism.sh $mode "$x" "$T/ref" "$T/w-$x") || { echo "$out"; fail "$x: the Slurm run's merged CSVs differ from the one-process run's"; }
  echo "slurm: $x $mode as a 3-task array (job $a, $cpus CPU(s) and thread(s) per task) and its merge (job $m): the one-process run's CSVs (apart from date and timing columns)"
done

# a failed task: shard 2 cannot create its folder (a file stands there); its log
# stays, the merge waits for ever, a rerun of the failed index merges
x=definiteness mode=--smoke
w=$T/w-fail
mkdir -p "$w"
: >"$w/shard-2"
submit "$w" "$mode" "$x"
s=$(wait_job "$m")
[ "$s" = NEVER ] || { show_logs "$w"; fail "failed task: the merge job $m ended '$s', not pending for ever"; }
[ -s "$w/logs/$x-${a}_2.log" ] || fail "failed task: its log $w/logs/$x-${a}_2.log is missing"
first=$m
fa=$a
rm -f "$w/shard-2"
BUILD=$B scripts/slurm-submit.sh --dir "$w" --rerun failed "$mode" "$x" 3 -- --cpus-per-task=1 >"$T/submit.out" 2>&1 ||
  { cat "$T/submit.out"; fail "slurm-submit.sh --rerun failed"; }
grep -q "shards 2 of 3" "$T/submit.out" || { cat "$T/submit.out"; fail "--rerun failed did not resubmit shard 2 alone"; }
grep -q "cancelled the earlier merge job $first" "$T/submit.out" || { cat "$T/submit.out"; fail "--rerun left the earlier merge job $first"; }
a=$(sed -n 's/^array job \([0-9]*\).*/\1/p' "$T/submit.out")
m=$(sed -n 's/^merge job \([0-9]*\).*/\1/p' "$T/submit.out")
s=$(wait_job "$m")
[ "$s" = "COMPLETED " ] || { show_logs "$w"; fail "rerun: merge job $m ended $s"; }
[ -s "$w/logs/$x-$(cat "$w/jobs/array.jobid")_2.log" ] && [ "$a" = "$(cat "$w/jobs/array.jobid")" ] || fail "rerun: no log of the rerun task"
[ -s "$w/logs/$x-${fa}_2.log" ] || fail "rerun: the failed task's log $x-${fa}_2.log is gone"
out=$(BUILD=$B tests/determinism.sh $mode "$x" "$T/ref" "$w") || { echo "$out"; fail "rerun: merged CSVs differ from the one-process run's"; }
echo "slurm: a failed task (its log kept, the merge never ran) and --rerun failed (shard 2 alone, job $a; merge job $m) give the one-process run's CSVs"
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
CB_QUIET=1 BUILD=$B scripts/slurm-submit.sh --dir "$T/w-all" --out "$T/all-out" --smoke all 3 >"$T/submit.out" 2>&1 || { cat "$T/submit.out"; fail "slurm-submit.sh --smoke all 3 failed"; }
a=$(sed -n 's/^array job \([0-9]*\).*/\1/p' "$T/submit.out")
m=$(sed -n 's/^merge job \([0-9]*\).*/\1/p' "$T/submit.out")
[ -n "$a" ] && [ -n "$m" ] || { cat "$T/submit.out"; fail "all: no job ids"; }
s=$(wait_job "$m")
[ "$s" = "COMPLETED " ] || { show_logs "$T/w-all"; fail "all: merge job $m ended $s (array job $a: $(wait_job "$a"))"; }
out=$(tests/verdicts.sh "$T/allref/REPORT.md" "$T/all-out/REPORT.md") || { echo "$out"; fail "all 3: the verdict table differs from the unsharded run's"; }
echo "slurm: --smoke all 3 (array job $a of 3 groups, merge job $m: merged, plotted, reported): $out"
echo "slurm: all passed"
