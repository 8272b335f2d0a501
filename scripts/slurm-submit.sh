#!/bin/sh
# Runs an experiment as a Slurm job array of N shards, then merges them:
#   scripts/slurm-submit.sh [OPTIONS] EXPERIMENT N [-- SBATCH_OPTIONS...]
#   scripts/slurm-submit.sh [OPTIONS] all N [-- SBATCH_OPTIONS...]
# "all": every experiment, its units balanced into N groups (scripts/all-run.sh,
# planned at submission; DIR default results/slurm/all-N): task I runs group
# I, then one merge job merges every experiment (merge-shards.sh's checks, one
# revision across all), draws the plots and writes OUT/REPORT.md (OUT a
# folder, default results/).
# Writes two job scripts to DIR/jobs/ and submits them:
#   - the array job (--array=1-N): task I runs build/EXPERIMENT --shard I/N
#     --out DIR/shard-I/EXPERIMENT.csv, with OpenBLAS and OpenMP threads equal
#     to the task's --cpus-per-task (SLURM_CPUS_PER_TASK, default 1) and
#     OpenMP threads bound to the task's CPUs (OMP_PROC_BIND=close,
#     OMP_PLACES=threads); each task has its own CPU lock (CB_CPU_LOCK), since
#     the allocation, not the lock, keeps the tasks off each other's CPUs;
#   - the merge job (--dependency=afterok:<array>): scripts/merge-shards.sh
#     into OUT, then the run's report: scripts/calibrate-hints on the shards'
#     cell lists (hints against measured seconds, and the shards' measured
#     loads against total/N).
# It prints both job ids ("array job <id>", "merge job <id>"). SBATCH_OPTIONS
# (--partition, --time, --cpus-per-task, --account ...) go to both sbatch calls.
# Logs: DIR/logs/EXPERIMENT-<jobid>_<I>.log per task and
# DIR/logs/EXPERIMENT-merge-<jobid>.log; a failed task's log stays (a rerun
# writes new ones under its own job id).
# Options:
#   --dry-run       print the two scripts and the sbatch commands; submit nothing
#   --quick | --smoke   the experiment's reduced runs
#   --shard-mode M  balanced (default) or modulo
#   --dir DIR       work folder (default results/slurm/EXPERIMENT-N)
#   --out OUT       the merged main CSV (default DIR/EXPERIMENT.csv)
#   --rerun LIST    resubmit only these shard indices (e.g. 3,7, or "failed":
#                   every shard without a complete output in DIR), then a new
#                   merge of all N; the earlier merge job, if still pending
#                   (its dependency failed), is cancelled
# BUILD (default build) is the build folder; the repository must be on a
# file system the compute nodes share (the jobs cd to it).
set -eu
usage() { echo "usage: $0 [--dry-run] [--quick|--smoke] [--shard-mode M] [--dir DIR] [--out OUT] [--rerun LIST|failed] EXPERIMENT N [-- SBATCH_OPTIONS]" >&2; exit 1; }
die() { echo "slurm-submit: $*" >&2; exit 1; }
dry=0 mode=balanced dir="" out="" rerun="" expopt=""
while [ $# -gt 0 ]; do
  case $1 in
    --dry-run) dry=1 ;;
    --quick | --smoke) expopt=$1 ;;
    --shard-mode) [ $# -ge 2 ] || usage; mode=$2; shift ;;
    --dir) [ $# -ge 2 ] || usage; dir=$2; shift ;;
    --out) [ $# -ge 2 ] || usage; out=$2; shift ;;
    --rerun) [ $# -ge 2 ] || usage; rerun=$2; shift ;;
    -h | --help) sed -n '2,/^set -eu/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --) break ;;
    -*) echo "slurm-submit: unknown option '$1'" >&2; usage ;;
    *) break ;;
  esac
  shift
done
[ $# -ge 2 ] || usage
exp=$1 n=$2
shift 2
if [ $# -gt 0 ]; then [ "$1" = -- ] || usage; shift; fi
if [ "$exp" = all ]; then # every experiment: an array of N groups (scripts/all-run.sh), then one merge, plots, report
  case $n in '' | *[!0-9]* | 0*) die "N '$n': expected a positive whole number" ;; esac
  case $rerun in failed) die "all: --rerun failed is not supported; give the failed groups' indices (--rerun 2,3)" ;; *[!0-9,]*) die "--rerun '$rerun': expected indices such as 3,7" ;; esac
  [ -z "$rerun" ] || rerun_all=$rerun
  repo=$(cd "$(dirname "$0")/.." && pwd)
  dir=${dir:-results/slurm/all-$n}
  out=${out:-results}
  case $dir in /*) ;; *) dir=$repo/$dir ;; esac
  case $out in /*) ;; *) out=$repo/$out ;; esac
  case $dir$out in *[!A-Za-z0-9_./+-]*) die "all: DIR and OUT may hold only letters, digits and _ . / + -" ;; esac
  m=${expopt:--}
  B=${BUILD:-build}
  case $B in /*) ;; *) B=$repo/$B ;; esac
  jobs=$dir/jobs logs=$dir/logs
  array=${rerun_all:-1-$n}
  a_script="#!/bin/sh
#SBATCH --job-name=cb-all
#SBATCH --array=$array
#SBATCH --cpus-per-task=1
#SBATCH --ntasks=1
#SBATCH --output=$logs/all-%A_%a.log
# clothbench: group \$SLURM_ARRAY_TASK_ID of $n of the whole run (scripts/slurm-submit.sh all)
set -eu
cd $repo
t=\${SLURM_CPUS_PER_TASK:-1}
export OPENBLAS_NUM_THREADS=\$t OMP_NUM_THREADS=\$t OMP_PROC_BIND=close OMP_PLACES=threads BUILD=$B
echo \"clothbench: group \$SLURM_ARRAY_TASK_ID/$n on \$(hostname), \$t thread(s)\" >&2
exec scripts/all-run.sh group $dir $m \$SLURM_ARRAY_TASK_ID"
  m_script="#!/bin/sh
#SBATCH --job-name=cb-all-merge
#SBATCH --cpus-per-task=1
#SBATCH --ntasks=1
#SBATCH --output=$logs/all-merge-%j.log
# clothbench: merge, plot and report the whole run (scripts/slurm-submit.sh all)
set -eu
cd $repo
BUILD=$B exec scripts/all-run.sh merge $dir $out"
  if [ $dry = 1 ]; then
    printf '# ---- %s\n%s\n# ---- %s\n%s\n' "$jobs/array.sh" "$a_script" "$jobs/merge.sh" "$m_script"
    echo "# ---- would run: scripts/all-run.sh plan $dir $m $n; sbatch --parsable $* $jobs/array.sh; sbatch --parsable --dependency=afterok:<array job> $* $jobs/merge.sh"
    exit 0
  fi
  command -v sbatch >/dev/null 2>&1 || die "sbatch not found (is this a Slurm login node?)"
  mkdir -p "$jobs" "$logs"
  if [ -z "$rerun" ]; then
    rm -rf "$dir/plan" "$dir"/*/shard-* "$dir"/*/whole
    BUILD=$B scripts/all-run.sh plan "$dir" "$m" "$n" || die "no plan (above)"
  fi
  printf '%s\n' "$a_script" > "$jobs/array.sh"
  printf '%s\n' "$m_script" > "$jobs/merge.sh"
  aid=$(sbatch --parsable "$@" "$jobs/array.sh") || die "sbatch of the array job failed"
  aid=${aid%%;*}
  mid=$(sbatch --parsable --dependency="afterok:$aid" "$@" "$jobs/merge.sh") || die "sbatch of the merge job failed"
  mid=${mid%%;*}
  echo "array job $aid (groups $array of $n, logs $logs/all-${aid}_<I>.log)"
  echo "merge job $mid (after the array succeeds: $out/REPORT.md, log $logs/all-merge-$mid.log)"
  exit 0
fi
# shellcheck source=scripts/lib/shards.sh
. "$(dirname "$0")/lib/shards.sh"
shards_check
shards_paths slurm
# the experiment can be sharded and has cells (a program that cannot exits 1 here, with its reason)
list=$(shards_cells slurm-submit) || die "$exp cannot run as shards (above)"
ncells=$(printf '%s\n' "$list" | grep -c .) || ncells=0
[ "$n" -le "$ncells" ] || echo "slurm-submit: warning: $n shards for $ncells cells: some shards have no cell" >&2
if [ -n "$rerun" ]; then
  if [ "$rerun" = failed ]; then
    rerun=$(shards_missing | tr ' ' ,)
    rerun=${rerun#,}
    [ -n "$rerun" ] || die "every shard of $dir has its output: nothing to rerun (the merge: scripts/merge-shards.sh)"
  fi
  for i in $(echo "$rerun" | tr , ' '); do
    case $i in '' | *[!0-9]* | 0*) die "--rerun '$rerun': expected indices such as 3,7" ;; esac
    [ "$i" -le "$n" ] || die "--rerun: shard $i of $n"
  done
  array=$rerun
else
  array=1-$n
fi
jobs=$dir/jobs
logs=$dir/logs
shards="" cellfiles=""
i=1
while [ "$i" -le "$n" ]; do
  shards="$shards $(q "$dir/shard-$i/$exp.csv")"
  cellfiles="$cellfiles $(q "$dir/shard-$i/$exp.csv.cells")"
  i=$((i + 1))
done
array_script() {
  cat <<EOF
#!/bin/sh
#SBATCH --job-name=cb-$exp
#SBATCH --array=$array
#SBATCH --cpus-per-task=1
#SBATCH --ntasks=1
#SBATCH --output=$logs/$exp-%A_%a.log
# clothbench: shard \$SLURM_ARRAY_TASK_ID of $n of $exp (scripts/slurm-submit.sh)
set -eu
cd $(q "$repo")
i=\$SLURM_ARRAY_TASK_ID
t=\${SLURM_CPUS_PER_TASK:-1}
export OPENBLAS_NUM_THREADS=\$t OMP_NUM_THREADS=\$t OMP_PROC_BIND=close OMP_PLACES=threads
export CB_CPU_LOCK=$(q "$dir/locks")/shard-\$i.lock
mkdir -p $(q "$dir/locks") $(q "$dir")/shard-\$i
echo "clothbench: $exp shard \$i/$n on \$(hostname), \$t thread(s), job \${SLURM_ARRAY_JOB_ID:-?}_\$i" >&2
exec $(q "$B/$exp") $expopt --shard "\$i/$n" --shard-mode $mode --out $(q "$dir")/shard-\$i/$(q "$exp.csv")
EOF
}
merge_script() {
  cat <<EOF
#!/bin/sh
#SBATCH --job-name=cb-$exp-merge
#SBATCH --cpus-per-task=1
#SBATCH --ntasks=1
#SBATCH --output=$logs/$exp-merge-%j.log
# clothbench: merge the $n shards of $exp (scripts/slurm-submit.sh)
set -eu
cd $(q "$repo")
scripts/merge-shards.sh $(q "$out")$shards
echo "clothbench: merged $n shards of $exp into "$(q "$out")
scripts/calibrate-hints$cellfiles
EOF
}
if [ $dry = 1 ]; then # nothing is written
  echo "# ---- $jobs/array.sh"
  array_script
  echo "# ---- $jobs/merge.sh"
  merge_script
  echo "# ---- would run:"
  echo "sbatch --parsable $* $jobs/array.sh"
  echo "sbatch --parsable --dependency=afterok:<array job> $* $jobs/merge.sh"
  exit 0
fi
command -v sbatch >/dev/null 2>&1 || die "sbatch not found (is this a Slurm login node?)"
mkdir -p "$jobs" "$logs"
array_script > "$jobs/array.sh.tmp.$$" && mv "$jobs/array.sh.tmp.$$" "$jobs/array.sh"
merge_script > "$jobs/merge.sh.tmp.$$" && mv "$jobs/merge.sh.tmp.$$" "$jobs/merge.sh"
chmod +x "$jobs/array.sh" "$jobs/merge.sh"
if [ -z "$rerun" ]; then # a fresh run: no shard output of an earlier one may be merged into it
  shards_clear
elif [ -f "$jobs/merge.jobid" ]; then # the earlier merge waits for an array that failed: it would never run
  old=$(cat "$jobs/merge.jobid")
  if squeue -h -j "$old" -o %T 2>/dev/null | grep -q PENDING; then scancel "$old" && echo "slurm-submit: cancelled the earlier merge job $old"; fi
fi
aid=$(sbatch --parsable "$@" "$jobs/array.sh") || die "sbatch of the array job failed"
aid=${aid%%;*}
mid=$(sbatch --parsable --dependency="afterok:$aid" "$@" "$jobs/merge.sh") || die "sbatch of the merge job failed (the array job $aid runs; merge by hand: sh $jobs/merge.sh)"
mid=${mid%%;*}
echo "$aid" > "$jobs/array.jobid"
echo "$mid" > "$jobs/merge.jobid"
echo "array job $aid (shards $array of $n, logs $logs/$exp-${aid}_<I>.log)"
echo "merge job $mid (after the array succeeds: $out, log $logs/$exp-merge-$mid.log)"
