#!/bin/sh
# Runs an experiment as N shards under GNU parallel, then merges them:
#   scripts/parallel-run.sh [OPTIONS] EXPERIMENT N [PARALLEL_OPTIONS...]
#   scripts/parallel-run.sh [OPTIONS] all N [PARALLEL_OPTIONS...]
# "all": every experiment, its units balanced into N groups (scripts/all-run.sh;
# DIR default results/parallel/all-N), job I runs group I; then one merge of
# every experiment, the plots and the report into OUT (a folder, default
# results/: results/REPORT.md).
# Job I runs build/EXPERIMENT --shard I/N --out DIR/shard-I/EXPERIMENT.csv,
# its output and progress going to DIR/logs/EXPERIMENT-shard-I.log, with
# OpenBLAS and OpenMP threads equal to --threads (default 1) and OpenMP
# threads bound (OMP_PROC_BIND=close, OMP_PLACES=threads); give parallel as
# many job slots as the cores hold (-j, default one per core), e.g. -j 4 with
# --threads 2 on 8 cores. Each job has its own CPU lock (CB_CPU_LOCK) unless
# --shared-lock is given (then timed experiments' shards on one machine take
# turns, so that their timings are not disturbed by each other).
# parallel runs with --joblog DIR/joblog --resume-failed: running the same
# command again (after an interruption, or after a shard failed) runs only
# the shards that failed or did not finish, and then merges. The merge
# (scripts/merge-shards.sh into OUT) runs once every shard has succeeded; then
# scripts/calibrate-hints reports the shards' measured loads.
# PARALLEL_OPTIONS go to parallel: -j, --sshlogin host1,host2 (the repository
# must be at the same path on every machine, on a shared file system), ...
# Options:
#   --quick | --smoke   the experiment's reduced runs
#   --shard-mode M  balanced (default) or modulo
#   --threads T     threads per shard (default 1)
#   --shared-lock   one CPU lock for all shards on a machine (see above)
#   --dir DIR       work folder (default results/parallel/EXPERIMENT-N)
#   --out OUT       the merged main CSV (default DIR/EXPERIMENT.csv)
#   --fresh         forget an earlier run in DIR (its joblog and shard outputs)
# A DIR whose earlier run had other settings (experiment options, N, mode,
# threads) is started afresh, with a message.
set -eu
usage() { echo "usage: $0 [--quick|--smoke] [--shard-mode M] [--threads T] [--shared-lock] [--dir DIR] [--out OUT] [--fresh] EXPERIMENT N [PARALLEL_OPTIONS]" >&2; exit 1; }
die() { echo "parallel-run: $*" >&2; exit 1; }
mode=balanced dir="" out="" expopt="" threads=1 fresh=0 shared=0
while [ $# -gt 0 ]; do
  case $1 in
    --quick | --smoke) expopt=$1 ;;
    --shard-mode) [ $# -ge 2 ] || usage; mode=$2; shift ;;
    --threads) [ $# -ge 2 ] || usage; threads=$2; shift ;;
    --shared-lock) shared=1 ;;
    --dir) [ $# -ge 2 ] || usage; dir=$2; shift ;;
    --out) [ $# -ge 2 ] || usage; out=$2; shift ;;
    --fresh) fresh=1 ;;
    -h | --help) sed -n '2,/^set -eu/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "parallel-run: unknown option '$1'" >&2; usage ;;
    *) break ;;
  esac
  shift
done
[ $# -ge 2 ] || usage
exp=$1 n=$2
shift 2
if [ "$exp" = all ]; then # every experiment: N groups of units (scripts/all-run.sh), then one merge, plots, report
  case $n in '' | *[!0-9]* | 0*) die "N '$n': expected a positive whole number" ;; esac
  command -v parallel >/dev/null 2>&1 || die "GNU parallel not found (Debian package parallel)"
  repo=$(cd "$(dirname "$0")/.." && pwd)
  dir=${dir:-results/parallel/all-$n}
  out=${out:-results}
  case $dir in /*) ;; *) dir=$repo/$dir ;; esac
  case $out in /*) ;; *) out=$repo/$out ;; esac
  case $dir$out in *[!A-Za-z0-9_./+-]*) die "all: DIR and OUT may hold only letters, digits and _ . / + -" ;; esac
  m=${expopt:--}
  settings="all $m N=$n threads=$threads"
  if [ $fresh = 1 ] || { [ -f "$dir/settings" ] && [ "$(cat "$dir/settings")" != "$settings" ]; }; then rm -rf "$dir"; fi
  mkdir -p "$dir/logs"
  [ -f "$dir/plan" ] || scripts/all-run.sh plan "$dir" "$m" "$n" || die "no plan (above)"
  printf '%s\n' "$settings" > "$dir/settings"
  echo "parallel-run: every experiment as $n groups (plan $dir/plan, joblog $dir/joblog, logs $dir/logs/group-<I>.log)" >&2
  rc=0
  seq 1 "$n" | parallel --joblog "$dir/joblog" --resume-failed "$@" \
    "OPENBLAS_NUM_THREADS=$threads OMP_NUM_THREADS=$threads OMP_PROC_BIND=close OMP_PLACES=threads $repo/scripts/all-run.sh group $dir $m {} >$dir/logs/group-{}.log 2>&1" || rc=$?
  if [ $rc != 0 ]; then
    for f in "$dir"/logs/group-*.log; do [ -f "$f" ] && { echo "--- $f" >&2; tail -3 "$f" >&2; }; done
  fi
  [ $rc = 0 ] || die "groups failed (parallel exit $rc; logs $dir/logs/group-<I>.log): run the same command again to rerun them"
  "$repo/scripts/all-run.sh" merge "$dir" "$out" || die "merge failed (above)"
  exit 0
fi
# shellcheck source=scripts/lib/shards.sh
. "$(dirname "$0")/lib/shards.sh"
shards_check
case $threads in '' | *[!0-9]* | 0*) die "--threads '$threads': expected a positive whole number" ;; esac
command -v parallel >/dev/null 2>&1 || die "GNU parallel not found (Debian package parallel)"
shards_paths parallel
# the experiment can be sharded (a program that cannot exits 1 here, with its reason)
shards_cells parallel-run >/dev/null || die "$exp cannot run as shards (above)"
settings="$B/$exp $expopt --shard ./$n --shard-mode $mode threads=$threads shared_lock=$shared"
if [ $fresh = 0 ] && [ -f "$dir/settings" ] && [ "$(cat "$dir/settings")" != "$settings" ]; then
  echo "parallel-run: $dir held a run with other settings ($(cat "$dir/settings")): starting afresh" >&2
  fresh=1
fi
if [ $fresh = 1 ]; then
  rm -f "$dir/joblog"
  shards_clear
fi
mkdir -p "$dir/logs" "$dir/locks"
printf '%s\n' "$settings" > "$dir/settings"
if [ $shared = 1 ]; then lock='${CB_CPU_LOCK:-/tmp/clothbench-cpu.lock}'; else lock="$(q "$dir/locks")/shard-{}.lock"; fi
# one shard: the command parallel runs (through a shell) with {} = I
job="cd $(q "$repo") && mkdir -p $(q "$dir")/shard-{} && OPENBLAS_NUM_THREADS=$threads OMP_NUM_THREADS=$threads OMP_PROC_BIND=close OMP_PLACES=threads CB_CPU_LOCK=$lock $(q "$B/$exp") $expopt --shard {}/$n --shard-mode $mode --out $(q "$dir")/shard-{}/$(q "$exp.csv") >$(q "$dir/logs")/$(q "$exp")-shard-{}.log 2>&1"
echo "parallel-run: $exp as $n shards (joblog $dir/joblog, logs $dir/logs/$exp-shard-<I>.log)" >&2
rc=0
seq 1 "$n" | parallel --joblog "$dir/joblog" --resume-failed "$@" "$job" || rc=$?
failed=$(awk 'NR > 1 && $7 != 0 { f = f " " $NF } END { print f }' "$dir/joblog" 2>/dev/null || true)
missing=$(shards_missing)
if [ $rc != 0 ] || [ -n "$missing" ]; then
  echo "parallel-run: shards without their output:${missing:- (none)} (parallel exit $rc; the joblog's failed jobs:${failed:- none})" >&2
  for i in $missing; do
    [ -f "$dir/logs/$exp-shard-$i.log" ] && { echo "--- $dir/logs/$exp-shard-$i.log" >&2; tail -3 "$dir/logs/$exp-shard-$i.log" >&2; }
  done
  echo "parallel-run: run the same command again to rerun only those shards, then merge" >&2
  exit 1
fi
shards=""
i=1
while [ "$i" -le "$n" ]; do shards="$shards $dir/shard-$i/$exp.csv"; i=$((i + 1)); done
# shellcheck disable=SC2086
scripts/merge-shards.sh "$out" $shards || die "merge failed (above)"
echo "parallel-run: merged $n shards of $exp into $out"
# shellcheck disable=SC2046
scripts/calibrate-hints $(for s in $shards; do printf ' %s.cells' "$s"; done)
