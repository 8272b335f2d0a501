# shellcheck shell=sh disable=SC2154 # exp, n, mode, expopt, dir: the runner's
# What the two cluster runners, scripts/parallel-run.sh and
# scripts/slurm-submit.sh, share; sourced by both (not run). The runner sets
# exp, n and mode (EXPERIMENT, N, --shard-mode), dir and out ("" for the
# defaults) and defines die (its message prefix), then calls:
#   shards_check       validates mode, N and EXPERIMENT
#   shards_paths ROOT  cds to the repository and sets repo, B (the build
#                      folder, $BUILD or build), dir (default
#                      results/ROOT/EXPERIMENT-N) and out (default
#                      DIR/EXPERIMENT.csv), each absolute; dies unless
#                      B/EXPERIMENT is built
#   shards_cells NAME  prints shard 1/N's cell list (--list-cells; NAME names
#                      its lock and scratch CSV under TMPDIR); fails when the
#                      experiment cannot run as shards (its reason on stderr)
#   shards_missing     prints the indices of the shards of DIR without their
#                      complete output (DIR/shard-I/EXPERIMENT.csv.cells), each
#                      after a space
#   shards_clear       removes every shard's outputs in DIR
#   q S                prints S shell-quoted
shards_check() {
  case $mode in balanced | modulo) ;; *) die "--shard-mode '$mode': expected balanced or modulo" ;; esac
  case $n in '' | *[!0-9]* | 0*) die "N '$n': expected a positive whole number" ;; esac
  case $exp in '' | */* | .*) die "EXPERIMENT '$exp': expected a program name such as topology" ;; esac
}
shards_paths() {
  repo=$(cd "$(dirname "$0")/.." && pwd)
  cd "$repo" || die "cannot enter $repo"
  B=${BUILD:-build}
  case $B in /*) ;; *) B=$repo/$B ;; esac
  [ -x "$B/$exp" ] || die "$B/$exp: not built (run: make $B/$exp)"
  dir=${dir:-results/$1/$exp-$n}
  case $dir in /*) ;; *) dir=$repo/$dir ;; esac
  out=${out:-$dir/$exp.csv}
  case $out in /*) ;; *) out=$repo/$out ;; esac
}
shards_cells() {
  # shellcheck disable=SC2086 # expopt is empty or one word
  CB_QUIET=1 CB_CPU_LOCK="${TMPDIR:-/tmp}/cb-$1.lock" "$B/$exp" $expopt --shard "1/$n" --shard-mode "$mode" \
    --list-cells --out "${TMPDIR:-/tmp}/cb-$1-$$.csv"
}
shards_missing() {
  i=1
  while [ "$i" -le "$n" ]; do
    [ -f "$dir/shard-$i/$exp.csv.cells" ] || printf ' %s' "$i"
    i=$((i + 1))
  done
}
shards_clear() {
  i=1
  while [ "$i" -le "$n" ]; do rm -f "$dir/shard-$i/$exp"*; i=$((i + 1)); done
}
q() { printf "'%s'" "$(printf %s "$1" | sed "s/'/'\\\\''/g")"; }
