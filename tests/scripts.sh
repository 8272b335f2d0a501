#!/bin/sh
# End-to-end checks of the shell scripts a user runs after the experiments:
# scripts/merge-shards.sh (issue 21, defects 7, 8, 9; issue 23: the cell
# lists), scripts/calibrate-hints (issue 23), scripts/timed-split.py and
# scripts/lib/all-plan.py --times (issue 37), scripts/plots.sh and
# scripts/movies.sh (defects 10, 17: paths are data, never code), scripts/readme-peers.py and
# scripts/readme-bench-contact.py (fixtures).
# Run from the repository root (make check does: BUILD=<dir> tests/scripts.sh).
set -u
B=${BUILD:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbscripts.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
fail=0 n=0
ok() { desc=$1; shift; n=$((n + 1)); "$@" || { echo "scripts: FAIL: $desc"; fail=1; }; }
export CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1

# ---- merge-shards.sh: two shards of definiteness --smoke (a main CSV and three side tables) ----
for i in 1 2; do
  "$B/definiteness" --smoke --shard $i/2 --out "$T/s$i/d.csv" >/dev/null 2>"$T/err" || { echo "scripts: FAIL: definiteness --shard $i/2:"; cat "$T/err"; exit 1; }
done
fresh() { rm -rf "$T/w1" "$T/w2" "$T/m"; cp -r "$T/s1" "$T/w1" && cp -r "$T/s2" "$T/w2"; }
merge() { scripts/merge-shards.sh "$T/m/d.csv" "$T/w1/d.csv" "$T/w2/d.csv" >"$T/merge.out" 2>"$T/merge.err"; }
nothing_written() { [ -z "$(ls "$T/m" 2>/dev/null)" ]; }
fresh
merge
ok "merge of two valid shards: exit 0" test $? -eq 0
ok "merge of two valid shards: the main CSV" test -s "$T/m/d.csv"
# defect 9: shards differing only in the environment they ran in (observed threads) merge,
# and the merged header keeps what each shard observed
fresh
sed -i 's/^# threads_observed: .*/# threads_observed: cholmod_factorize 2, dgemm 2 (edited)/' "$T/w2/d.csv" "$T/w2"/d_*.csv
merge
ok "defect 9: shards whose threads_observed differ do not merge: $(cat "$T/merge.err")" test -s "$T/m/d.csv"
ok "defect 9: the merged header lacks shard 2's threads_observed" grep -q '^# shard 2 threads_observed: cholmod_factorize 2, dgemm 2 (edited)' "$T/m/d.csv"
# ... but a difference in what was run (a config key) still refuses the merge
fresh
sed -i 's/^# quick: 1$/# quick: 0/' "$T/w2/d.csv"
merge
ok "shards of different runs (quick 1 and 0) merged" test $? -ne 0
ok "a refused merge left files: $(ls "$T/m" 2>/dev/null)" nothing_written
# defect 7: a shard cut mid-row is refused (with and without its last newline); shard 1's
# main CSV has rows under its header (shard 2's may have none: the smoke run's cells)
fresh
last=$(tail -n 1 "$T/w1/d.csv")
sed -i '$d' "$T/w1/d.csv"
printf '%s\n' "$(echo "$last" | cut -d, -f1-2)" >>"$T/w1/d.csv"
merge
ok "defect 7: a 2-field row merged under the header" test $? -ne 0
ok "defect 7: the message names the cut row" grep -q 'fields under a header of' "$T/merge.err"
ok "defect 7: a merge of a cut shard left files" nothing_written
fresh
printf '%s' "$(head -c -10 "$T/w1/d.csv")" >"$T/w1/cut" && mv "$T/w1/cut" "$T/w1/d.csv"
merge
ok "defect 7: a shard without its final newline merged" test $? -ne 0
ok "defect 7: the message says it does not end with a newline" grep -q 'does not end with a newline' "$T/merge.err"
# defect 8: a missing third side table leaves nothing, not the main CSV and two side tables
fresh
third=$(ls "$T/w2"/d_*.csv | sed -n 3p)
rm -f "$third"
merge
ok "defect 8: a missing side table merged" test $? -ne 0
ok "defect 8: a failed merge left a partial merge: $(ls "$T/m" 2>/dev/null | tr '\n' ' ')" nothing_written
ok "defect 8: temporary files left" test -z "$(ls "$T/m" 2>/dev/null | grep merge)"
# issue 23: the merge is keyed by each shard's cell list: every cell exactly once, one shard mode
fresh
merge
ok "issue 23: the merged cell list (OUT.csv.cells) lacks the 2 cells" test "$(sed 1,2d "$T/m/d.csv.cells" | wc -l)" = 2
fresh
sed -n 3p "$T/w1/d.csv.cells" >>"$T/w2/d.csv.cells"
merge
ok "issue 23: a cell listed by two shards merged" test $? -ne 0
ok "issue 23: the message names the twice-listed cell: $(cat "$T/merge.err")" grep -q 'cell 0 is listed by two shards' "$T/merge.err"
ok "issue 23: a refused merge left files" nothing_written
fresh
sed -i 3d "$T/w2/d.csv.cells"
merge
ok "issue 23: a shard's cell missing merged" test $? -ne 0
ok "issue 23: the message names the missing cell: $(cat "$T/merge.err")" grep -q 'cell 1 is listed by no shard' "$T/merge.err"
fresh
sed -i '1s/ balanced$/ modulo/' "$T/w2/d.csv.cells"
merge
ok "issue 23: shards of two shard modes merged" test $? -ne 0
ok "issue 23: the message names the shard mode: $(cat "$T/merge.err")" grep -q 'shard-mode' "$T/merge.err"

# ---- calibrate-hints: hints against measured seconds (a fixture: 8 of 10 cells within 2x, one 10x off) ----
{ echo "shard 1 1 10 balanced"; echo "tables -"
  for i in 0 1 2 3 4 5 6 7; do echo "$i 1 0 fix $i 2 0.5"; done
  echo "8 1 0 fix 8 2 5"; echo "9 1 0 fix 9 2 0.1"; } >"$T/fix.cells"
scripts/calibrate-hints "$T/fix.cells" >"$T/cal.out" 2>&1
ok "calibrate-hints on a fixture failed: $(cat "$T/cal.out")" test $? -eq 0
ok "calibrate-hints: not 8 of 10 within 2x: $(cat "$T/cal.out")" grep -q 'within 2x: 8 of 10 cells (80.0%)' "$T/cal.out"
ok "calibrate-hints: the worst ratio is not cell 8's 10: $(cat "$T/cal.out")" grep -q 'worst ratio: 10 (cell 8, fix 8' "$T/cal.out"
scripts/calibrate-hints --min-within2 0.9 "$T/fix.cells" >/dev/null 2>&1
ok "calibrate-hints --min-within2 0.9 passed 80%" test $? -eq 1
scripts/calibrate-hints --min-within2 0.8 "$T/fix.cells" >/dev/null 2>&1
ok "calibrate-hints --min-within2 0.8 failed 80%" test $? -eq 0
sed -i '$d' "$T/fix.cells"
scripts/calibrate-hints "$T/fix.cells" >/dev/null 2>"$T/cal.err"
ok "calibrate-hints: a run with a cell missing accepted" grep -q 'cells \[9\] are not in the files given' "$T/cal.err"

# ---- plots.sh and movies.sh: quotes, spaces and gnuplot code in the paths are data ----
if command -v gnuplot >/dev/null 2>&1; then
  R="$T/res x';system('touch $T/PWNED');a='"
  mkdir -p "$R"
  "$B/definiteness" --smoke --out "$R/definiteness.csv" >/dev/null 2>"$T/err" || { echo "scripts: FAIL: definiteness --smoke:"; cat "$T/err"; exit 1; }
  O="$T/out 'q \$HOME"
  RESULTS="$R" PLOTS_OUT="$O" scripts/plots.sh >"$T/plots.out" 2>"$T/plots.err"
  ok "defect 10: plots.sh with a quote in RESULTS failed: $(head -c 300 "$T/plots.err")" test $? -eq 0
  ok "defect 10: a path in RESULTS ran as gnuplot code" test ! -e "$T/PWNED"
  ok "defect 10: no definiteness_h1.png in PLOTS_OUT" test -s "$O/definiteness_h1.png"
  ok "defect 10: no success line for definiteness" grep -q "^plots: definiteness -> $O/" "$T/plots.out"
  W="$T/work 'a b"
  BUILD=$B MOVIES_ONLY=explicit_blowup MOVIES_STEPS=3 MOVIES_WORK="$W" PLOTS_OUT="$O" scripts/movies.sh >"$T/movies.out" 2>"$T/movies.err"
  ok "defect 17: movies.sh with a space and a quote in MOVIES_WORK and PLOTS_OUT failed: $(head -c 300 "$T/movies.err")" test $? -eq 0
  ok "defect 17: no movie GIF" test -s "$O/movie_E1_explicit_blowup.gif"
else
  echo "scripts: notice: gnuplot not installed (make deps); plots.sh and movies.sh not checked"
fi

# ---- readme-peers.py: the peer table comes from the two bench CSVs of one run, or not at all ----
P="$T/peers"
mkdir -p "$P"
hdr="n,dofs,nnz,peer,clothbench,phase,rounds,peer_ms,peer_min_ms,peer_max_ms,clothbench_ms,clothbench_min_ms,clothbench_max_ms,peer_over_clothbench,peer_over_clothbench_min,peer_over_clothbench_max,peer_rel_residual,clothbench_rel_residual,peer_detail,status"
{ printf '# program: bench_peers\n# git_revision: abc123\n# blas_kernel: Haswell\n# blas_kernel_choice: chosen (fixture)\n%s\n' "$hdr"
  for ph in analyse factorise analyse_factorise solve total; do
    echo "128,49146,1022886,mumps,cholmod,$ph,5,28,27,30,10,9,11,2.8,2.6,3.1,4e-15,5e-15,SCOTCH,ok"
  done; } >"$P/bench_peers.csv"
{ printf '# program: bench/peers_scipy.py\n# scipy: 1.10.1\n# scipy_blas_kernel: Haswell (fixture)\n# git_revision: abc123\n# blas_kernel: Haswell\n%s\n' "$hdr"
  echo "128,49146,1022886,scipy_cg,cg,iteration,5,3,2.9,3.2,1,0.9,1.1,3.0,2.8,3.3,1e-3,1e-3,100 iterations,ok"; } >"$P/bench_peers_scipy.csv"
printf 'head\n<!-- peers:begin -->\nold\n<!-- peers:end -->\ntail\n' >"$P/README.md"
${PYTHON:-/usr/bin/python3} scripts/readme-peers.py "$P" "$P/README.md" 2>"$T/peers.err"
ok "readme-peers.py on one run's CSVs failed: $(cat "$T/peers.err")" test $? -eq 0
ok "readme-peers.py: no MUMPS factorisation ratio from the CSV" grep -q '| MUMPS (sequential, SPD mode) | 128² | 5 | 2.80× (2.60–3.10) | 2.80× (2.60–3.10) |' "$P/README.md"
ok "readme-peers.py: no cg ratio" grep -q "| SciPy \`cg\` | 128² | 5 | – | – | – | – | – | 3.00× (2.80–3.30) |" "$P/README.md"
ok "readme-peers.py: the kernel is not stated" grep -q 'OpenBLAS kernel: Haswell (chosen (fixture))' "$P/README.md"
ok "readme-peers.py: the old block or the text around it" sh -c "! grep -q '^old$' '$P/README.md' && grep -q '^tail$' '$P/README.md'"
cp "$P/README.md" "$P/README.before"
sed -i 's/^# scipy_blas_kernel: Haswell/# scipy_blas_kernel: Prescott/' "$P/bench_peers_scipy.csv"
${PYTHON:-/usr/bin/python3} scripts/readme-peers.py "$P" "$P/README.md" 2>"$T/peers.err"
ok "readme-peers.py accepted SciPy on another kernel than clothbench" test $? -ne 0
ok "readme-peers.py changed the README on a refused run" cmp -s "$P/README.md" "$P/README.before"
sed -i 's/^# scipy_blas_kernel: Prescott/# scipy_blas_kernel: Haswell/; s/^# git_revision: abc123/# git_revision: def456/' "$P/bench_peers_scipy.csv"
${PYTHON:-/usr/bin/python3} scripts/readme-peers.py "$P" "$P/README.md" 2>"$T/peers.err"
ok "readme-peers.py accepted CSVs of two builds" test $? -ne 0
printf 'no markers\n' >"$P/README.md"
${PYTHON:-/usr/bin/python3} scripts/readme-peers.py "$P" "$P/README.md" 2>"$T/peers.err"
ok "readme-peers.py accepted a README without the markers" test $? -ne 0

# ---- readme-bench-contact.py: the contact block and its verdict on issue 34's 10x target, from a fixture ----
C="$T/bcontact"
mkdir -p "$C"
chdr="n,vertices,method,warmup_steps,steps_timed,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,broad_ms,ccd_ms,barrier_ms,solve_ms,rest_ms,assemble_ms,newton_iters,contacts,n_candidates,ratio,min_ratio,max_ratio,target_ratio,status"
contact_csv() { # $1: the 64^2 ratio (empty: not measured)
  { printf '# program: bench_contact\n# git_revision: abc123\n# quick: 0\n# blas_kernel: Haswell\n# blas_kernel_choice: chosen (fixture)\n%s\n' "$chdr"
    echo "64,4096,ipc,8,3,400,380,420,400;380;420,3,40,20,100,200,40,150,40,500,30000,$1,3,5,10,ok"
    echo "64,4096,none,8,3,80,78,90,80;78;90,3,0,0,0,70,10,5,17,0,0,,,,,ok"; } >"$C/bench_contact.csv"
}
contact_csv 5
printf 'head\n<!-- bench-contact:begin -->\nold\n<!-- bench-contact:end -->\ntail\n' >"$C/perf.md"
${PYTHON:-/usr/bin/python3} scripts/readme-bench-contact.py "$C" "$C/perf.md" 2>"$T/bc.err"
ok "readme-bench-contact.py on a fixture failed: $(cat "$T/bc.err")" test $? -eq 0
ok "readme-bench-contact.py: the ipc row (step, shares of it)" grep -q '| 64² (4096 vertices) | ipc | 400 ms (380–420) | 40 ms (10%) | 20 ms (5%) | 100 ms (25%) | 200 ms (50%) | 40 ms (10%) | 40 | 500 | 30000 | ok |' "$C/perf.md"
ok "readme-bench-contact.py: 5x within 10x not reported met" grep -q '64²: ipc / none = 5× (3–5× over 3 paired repeats); target at 64²: at most 10×: \*\*met\*\*; the largest phase: linear solve (50% of the step)' "$C/perf.md"
ok "readme-bench-contact.py: the old block or the text around it" sh -c "! grep -q '^old$' '$C/perf.md' && grep -q '^tail$' '$C/perf.md'"
contact_csv 12
${PYTHON:-/usr/bin/python3} scripts/readme-bench-contact.py "$C" "$C/perf.md" 2>"$T/bc.err"
ok "readme-bench-contact.py: 12x passed the 10x target" grep -q 'at most 10×: \*\*not met\*\*' "$C/perf.md"
contact_csv ""
${PYTHON:-/usr/bin/python3} scripts/readme-bench-contact.py "$C" "$C/perf.md" 2>"$T/bc.err"
ok "readme-bench-contact.py: a missing ratio is not 'not measured'" grep -q 'at most 10×: \*\*not measured\*\*' "$C/perf.md"
printf 'no markers\n' >"$C/perf.md"
${PYTHON:-/usr/bin/python3} scripts/readme-bench-contact.py "$C" "$C/perf.md" 2>"$T/bc.err"
ok "readme-bench-contact.py accepted a page without the markers" test $? -ne 0
ok "readme-bench-contact.py changed a page without the markers" grep -qx 'no markers' "$C/perf.md"

# ---- timed-split.py: the split and the bound on a fixture (numbers worked by hand) ----
# explicit_stability locks per cell: 60 s timed, 40 s untimed cells, 10 s outside cells (counted untimed);
# locking locks as a whole: its 100 s are timed. T = 160, U = 50: 160 + max(50/2, 50) = 210 s.
S=$T/split
mkdir -p "$S/share"
printf 'wall_s: 110.0\nquick: 0\ntimed_cells_s: 60.000\nuntimed_cells_s: 40.000\ncell_locks: 1\ncell 0 1 60.0 map\ncell 1 0 40.0 map\n' >"$S/explicit_stability.runtime"
printf 'wall_s: 100.0\nquick: 0\ntimed_cells_s: 95.000\nuntimed_cells_s: 0.000\ncell_locks: 0\n' >"$S/locking.runtime"
TS="${PYTHON:-/usr/bin/python3} scripts/timed-split.py"
$TS "$S" >"$T/ts.out" 2>&1
ok "timed-split.py on a fixture: $(cat "$T/ts.out")" grep -q '= 2 min 40 s + max(25.0 s, 50.0 s (explicit_stability)) = \*\*3 min 30 s\*\*' "$T/ts.out"
# --shares: locking's 95 cell seconds split by a per-cell run's share (70 % untimed): 28.5 timed, 66.5 + 5 untimed;
# T = 88.5, U = 121.5: 88.5 + max(60.75, 71.5) = 160 s
printf 'wall_s: 10.0\nquick: 1\ntimed_cells_s: 3.000\nuntimed_cells_s: 7.000\ncell_locks: 1\n' >"$S/share/locking.runtime"
$TS --shares "$S/share" "$S" >"$T/ts.out" 2>&1
ok "timed-split.py --shares: $(cat "$T/ts.out")" grep -q '= 1 min 28 s + max(1 min 01 s, 1 min 12 s (locking)) = \*\*2 min 40 s\*\*' "$T/ts.out"
ok "timed-split.py --shares: the estimate not said" grep -q 'locking | 1 min 40 s | 28.5 s | 1 min 12 s | estimated: 70 % untimed' "$T/ts.out"
# shard-runtime.sh: locking run as two processes (make experiments' RUN_SHARDS). Shard 1 ran 80 s: 10 s timed,
# 5 s waiting, so 65 s untimed work; shard 2 ran 31 s, all untimed. Summed: T = 60 + 10 = 70, U = 50 + 96 = 146,
# and one process's longest untimed share is 65 s (not 96): 70 + max(73, 65) = 143 s
now=$(date +%s)
printf 'start_s: %d\nend_s: %d\ntimed_cells_s: 10.000\nuntimed_cells_s: 60.000\ncell_locks: 1\nlock_wait_s: 5.000\ncell 2 1 10.0 F1\ncell 0 0 60.0 L2\n' \
  $((now - 80)) "$now" >"$S/l1.run"
printf 'start_s: %d\nend_s: %d\ntimed_cells_s: 0.000\nuntimed_cells_s: 29.000\ncell_locks: 1\nlock_wait_s: 0.000\ncell 1 0 29.0 L2\n' \
  $((now - 79)) $((now - 48)) >"$S/l2.run"
scripts/shard-runtime.sh 0 "$S/l1.run" "$S/l2.run" >"$S/locking.runtime" 2>"$T/sr.err"
ok "shard-runtime.sh failed: $(cat "$T/sr.err")" test $? -eq 0
ok "shard-runtime.sh: sums and cell order: $(tr '\n' ' ' <"$S/locking.runtime")" \
  awk '/^processes:/ && $2 == 2 { a++ } /^untimed_work_s:/ && $2 == 96 { a++ } /^longest_untimed_s:/ && $2 == 65 { a++ }
       /^timed_cells_s:/ && $2 == 10 { a++ } /^cell / { o = o $2 } END { exit !(a == 4 && o == "012") }' "$S/locking.runtime"
$TS "$S" >"$T/ts.out" 2>&1
ok "timed-split.py on a run of two processes: $(cat "$T/ts.out")" \
  grep -q '= 1 min 10 s + max(1 min 13 s, 1 min 05 s (locking)) = \*\*2 min 23 s\*\*' "$T/ts.out"
printf 'start_s: 1\ntimed_cells_s: 0.000\n' >"$S/l3.run"
scripts/shard-runtime.sh 0 "$S/l1.run" "$S/l3.run" >"$T/sr.out" 2>"$T/sr.err"
ok "shard-runtime.sh accepted a shard record without its end" test $? -ne 0
ok "shard-runtime.sh: the bad record not named: $(cat "$T/sr.err")" grep -q 'l3.run: no start_s or end_s' "$T/sr.err"
printf 'wall_s: ten\n' >"$S/locking.runtime"
$TS "$S" >"$T/ts.out" 2>&1
ok "timed-split.py accepted a run-time file that is not one" test $? -eq 2
ok "timed-split.py: the bad file not named: $(cat "$T/ts.out")" grep -q 'locking.runtime: not a run-time file' "$T/ts.out"

# ---- a program without cells (bending) lists none and runs nothing under --list-cells (all-plan.py asks every
#      experiment; bending used to run whole there) ----
"$B/bending" --smoke --list-cells --out "$T/bl.csv" >"$T/bl.out" 2>&1
ok "bending --list-cells: exit $?" test $? -eq 0
ok "bending --list-cells printed: $(cat "$T/bl.out")" test ! -s "$T/bl.out"
ok "bending --list-cells wrote its CSV" test ! -e "$T/bl.csv"

# ---- all-plan.py --times: a recorded run balances by its cell times, not by hints x wall time ----
# topology's --smoke cells, recorded: cell 0 takes 100 s, the others 1 s each; the plan's topology units then
# cost the recorded seconds (their sum is the recorded total), and a recorded run of another mode is refused
R=$T/rec
mkdir -p "$R"
"$B/topology" --smoke --list-cells --out "$T/l.csv" >"$T/cells.txt"
{ printf 'wall_s: 200.0\nquick: 1\ntimed_cells_s: 0\nuntimed_cells_s: 0\ncell_locks: 0\n'
  awk '{ printf "cell %d 0 %s %s\n", $1, $1 == 0 ? "100.0" : "1.0", $3 }' "$T/cells.txt"; } >"$R/topology.runtime"
want=$(awk 'END { print 100 + NR - 1 }' "$T/cells.txt")
${PYTHON:-/usr/bin/python3} scripts/lib/all-plan.py "$B" --smoke 2 docs/running.md --times "$R" >"$T/plan" 2>"$T/plan.err"
ok "all-plan.py --times failed: $(cat "$T/plan.err")" test $? -eq 0
got=$(awk '$2 == "topology" { s += $5 } END { printf "%g", s }' "$T/plan")
ok "all-plan.py --times: topology's units cost $got s, not the recorded $want s" test "$got" = "$want"
ok "all-plan.py --times: the 100 s cell is not a unit of its own" awk '$2 == "topology" && $5 == 100 { f = 1 } END { exit !f }' "$T/plan"
${PYTHON:-/usr/bin/python3} scripts/lib/all-plan.py "$B" "" 2 docs/running.md --times "$R" >/dev/null 2>"$T/plan.err"
ok "all-plan.py --times accepted a quick run's times for a full plan" test $? -ne 0

[ $fail = 0 ] && echo "scripts: ok ($n checks)"
exit $fail
