#!/bin/sh
# The run-time record (results/<name>.runtime) of an experiment that make
# experiments ran as several processes (RUN_SHARDS), from each shard's .run
# file (its start and end, then its <out>.split):
#   scripts/shard-runtime.sh QUICK SHARD1.run ... SHARDN.run > NAME.runtime
# wall_s runs from the first shard's start to now (the merge included); the
# timed and untimed cell seconds and the lock waits are summed over the
# shards, and the cell lines listed in cell order. untimed_work_s is every
# second a shard did not spend in timed cells or waiting for the lock (its
# untimed cells, set-up and writing: the work that may share the CPU), and
# longest_untimed_s the largest such share of one process, which
# scripts/timed-split.py uses for the bound (one process's untimed work runs
# one after another).
set -eu
[ $# -ge 2 ] || { echo "usage: $0 QUICK SHARD1.run ... SHARDN.run" >&2; exit 1; }
quick=$1; shift
for f in "$@"; do [ -s "$f" ] || { echo "shard-runtime: $f: missing or empty" >&2; exit 1; }; done
now=$(date +%s.%N)
awk -v now="$now" -v quick="$quick" -v n=$# '
  function finish() {
    if (s == "" || e == "") { print "shard-runtime: " prev ": no start_s or end_s line" > "/dev/stderr"; bad = 1; exit 1 }
    u = (e - s) - t - w; if (u < 0) u = 0
    UW += u; if (u > LU) LU = u
  }
  FNR == 1 { if (NR > 1) finish(); s = ""; e = ""; t = 0; w = 0; prev = FILENAME }
  $1 == "start_s:" { s = $2; if (first == "" || s < first) first = s }
  $1 == "end_s:" { e = $2 }
  $1 == "timed_cells_s:" { t = $2; T += $2 }
  $1 == "untimed_cells_s:" { U += $2 }
  $1 == "lock_wait_s:" { w = $2; W += $2 }
  $1 == "cell_locks:" { L = $2 }
  $1 == "cell" { cells[$2] = $0; if ($2 + 0 > max) max = $2 + 0 }
  END {
    if (bad) exit 1
    finish()
    printf "wall_s: %.1f\nquick: %d\nprocesses: %d\n", now - first, quick, n
    printf "timed_cells_s: %.3f\nuntimed_cells_s: %.3f\ncell_locks: %d\nlock_wait_s: %.3f\n", T, U, L, W
    printf "untimed_work_s: %.3f\nlongest_untimed_s: %.3f\n", UW, LU
    for (i = 0; i <= max; i++) if (i in cells) print cells[i]
  }' "$@"
