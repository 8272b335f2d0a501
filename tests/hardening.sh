#!/bin/sh
# Issue 35 (hardening, round 3): the scripts and programs as a hostile user
# drives them. Each check names its item; each failed before its fix.
# Run from the repository root (make check does: BUILD=<dir> tests/hardening.sh).
set -u
B=${BUILD:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbharden.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
fail=0 n=0
ok() { desc=$1; shift; n=$((n + 1)); "$@" || { echo "hardening: FAIL: $desc"; fail=1; }; }
export CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 CB_CPU_LOCK="$T/cpu.lock" # untimed: no wait for the others

# ---- item 1: the Slurm merge job runs nothing from --out; item 16: nor re-splits --dir ----
D="$T/slurm  two" # two spaces
O="$T/out\$(touch $T/PWNED1)\`touch $T/PWNED2\`.csv"
scripts/slurm-submit.sh --dry-run --smoke --dir "$D" --out "$O" definiteness 2 >"$T/dry.out" 2>"$T/dry.err"
ok "slurm-submit --dry-run failed: $(cat "$T/dry.err")" test $? -eq 0
sed -n '/^# ---- .*merge.sh$/,/^# ---- would run/p' "$T/dry.out" | grep '^echo "clothbench: merged' >"$T/echo.sh"
ok "item 1: no merge echo line in the merge job" test -s "$T/echo.sh"
sh "$T/echo.sh" >"$T/echo.out" 2>&1
ok "item 1: \$(...) in --out ran in the merge job's echo" test ! -e "$T/PWNED1"
ok "item 1: a backquote in --out ran in the merge job's echo" test ! -e "$T/PWNED2"
ok "item 1: the echo does not print --out as given: $(cat "$T/echo.out")" grep -qF "into $O" "$T/echo.out"
sed -n '/^# ---- .*merge.sh$/,/^# ---- would run/p' "$T/dry.out" | grep '^scripts/calibrate-hints' |
  sed "s|^scripts/calibrate-hints|printf '%s\\\\n'|" >"$T/cal.sh"
sh "$T/cal.sh" >"$T/cal.out" 2>&1
printf '%s\n' "$D/shard-1/definiteness.csv.cells" "$D/shard-2/definiteness.csv.cells" >"$T/cal.want"
ok "item 16: the merge job's calibrate-hints paths are not --dir's: $(cat "$T/cal.out")" cmp -s "$T/cal.out" "$T/cal.want"

# ---- items 4 and 16: merge-shards.sh refuses an output that is an input; paths with spaces merge ----
S="$T/sh  a'b"
for i in 1 2; do
  "$B/definiteness" --smoke --shard $i/2 --out "$S/s$i/d.csv" >/dev/null 2>"$T/err" || { echo "hardening: FAIL: definiteness --shard $i/2:"; cat "$T/err"; exit 1; }
done
scripts/merge-shards.sh "$S/m/d.csv" "$S/s1/d.csv" "$S/s2/d.csv" >/dev/null 2>"$T/merge.err"
ok "item 16: shards under a folder with two spaces and a quote do not merge: $(cat "$T/merge.err")" test -s "$S/m/d.csv"
ok "item 16: no merged cell list" test -s "$S/m/d.csv.cells"
cp -r "$S/s1" "$S/keep1"
scripts/merge-shards.sh "$S/s1/d.csv" "$S/s1/d.csv" "$S/s2/d.csv" >/dev/null 2>"$T/merge.err"
ok "item 4: a merge into shard 1's own path exited 0" test $? -ne 0
ok "item 4: the refusal does not say the output is an input: $(cat "$T/merge.err")" grep -q 'is the input' "$T/merge.err"
ok "item 4: shard 1's files changed" diff -r "$S/s1" "$S/keep1"
side=$(cd "$S/s2" && ls d_*.csv | head -n 1)
scripts/merge-shards.sh "$S/s2/$side" "$S/s1/d.csv" "$S/s2/d.csv" >/dev/null 2>"$T/merge.err"
ok "item 4: a merge into shard 2's side table exited 0" test $? -ne 0
scripts/merge-shards.sh "$S/m/d.csv" "$S/s1/d.csv" "$S/s2/d.csv" >/dev/null 2>"$T/merge.err"
ok "item 4: the merge again, after the refusals, failed: $(cat "$T/merge.err")" test $? -eq 0

# ---- item 3: an experiment's --out may not replace a config, a mesh or another input ----
C="$T/configs"
cp -r configs "$C"
cp -r configs "$T/configs.orig"
for o in "$C/hanging.ini" "$C/x.ini" "$C/new.csv" "$C/drape_irregular.obj" "$T/elsewhere.ini"; do
  "$B/topology" --smoke --configs "$C" --out "$o" >/dev/null 2>"$T/err"
  ok "item 3: topology --configs DIR --out $o exited 0" test $? -ne 0
  ok "item 3: topology --out $o: no refusal message: $(cat "$T/err")" grep -q 'refusing' "$T/err"
done
ok "item 3: the configs folder changed" diff -r "$C" "$T/configs.orig"
ok "item 3: --out elsewhere.ini was written" test ! -e "$T/elsewhere.ini"

# ---- item 5: tier-times.sh --all keeps the last full run's results (a fake make records what ran where) ----
F="$T/fake"
mkdir -p "$F/scripts" "$F/results" "$F/plots/out" "$F/bin"
cp scripts/tier-times.sh "$F/scripts/"
echo "full run" >"$F/results/topology.csv"
echo "full plot" >"$F/plots/out/a.png"
printf 'x\n<!-- tier-times:begin -->\n<!-- tier-times:end -->\n' >"$F/README.md"
cat >"$F/bin/make" <<'MAKE'
#!/bin/sh
if [ "$1" = -C ]; then cd "$2" || exit 1; shift 2; fi
case " $* " in
  *" experiments "*) mkdir -p results plots/out && echo quick >results/topology.csv && echo quick >plots/out/a.png ;;
  *" test "*) echo "experiments: topology --smoke 1.0 s" ;;
esac
exit 0
MAKE
chmod +x "$F/bin/make"
(cd "$F" && git init -q . && git -c user.name=t -c user.email=t@t commit -q --allow-empty -m t && PATH="$F/bin:$PATH" scripts/tier-times.sh --all README.md) >"$T/tier.out" 2>&1
ok "item 5: tier-times.sh --all with a fake make failed: $(tail -n 5 "$T/tier.out")" test $? -eq 0
ok "item 5: tier-times.sh --all replaced results/ with its quick run" grep -qx "full run" "$F/results/topology.csv"
ok "item 5: tier-times.sh --all replaced plots/out with its quick run" grep -qx "full plot" "$F/plots/out/a.png"

# ---- item 6: an interrupted simulate --frames leaves the earlier run's frames, CSV and OBJ, which agree ----
FR="$T/frames"
"$B/simulate" configs/hanging.ini --steps 3 --quiet --frames "$FR" --csv "$T/fr.csv" --obj "$T/fr.obj" 2>"$T/err"
ok "item 6: the first run failed: $(cat "$T/err")" test $? -eq 0
cp -r "$FR" "$T/frames.first"
cp "$T/fr.csv" "$T/fr.csv.first"
"$B/simulate" configs/hanging.ini --steps 1000000 --quiet --frames "$FR" --csv "$T/fr.csv" --obj "$T/fr.obj" 2>"$T/err" &
pid=$!
k=0
until ls "$FR"/.incomplete-frames.*/frame_000005.obj >/dev/null 2>&1 || [ $k -ge 300 ]; do sleep 0.1; k=$((k + 1)); done
ok "item 6: no frame staged after 30 s (or frames not staged in DIR/.incomplete-frames.<pid>)" test $k -lt 300
kill -TERM $pid 2>/dev/null
wait $pid 2>/dev/null
same_frames() { diff -r -x '.incomplete-frames.*' "$FR" "$T/frames.first" >/dev/null 2>&1; }
ok "item 6: the earlier frames were removed or mixed with the interrupted run's: $(ls "$FR" | head -n 8 | tr '\n' ' ')" same_frames
ok "item 6: the CSV is not the earlier run's" cmp -s "$T/fr.csv" "$T/fr.csv.first"
"$B/simulate" configs/hanging.ini --steps 2 --frames "$FR" --csv "$T/fr.csv" --obj "$T/fr.obj" 2>"$T/err"
ok "item 6: the run after the interrupted one failed: $(cat "$T/err")" test $? -eq 0
ok "item 6: the run after: not frames 0-2 alone: $(ls -A "$FR" | head -n 8 | tr '\n' ' ')" test "$(ls -A "$FR" | tr '\n' ' ')" = "frame_000000.obj frame_000001.obj frame_000002.obj "
ok "item 6: the earlier run's frames removed without a word" grep -q 'removed 4 frames of an earlier run' "$T/err"
# Also: --quiet prints nothing of the frames
"$B/simulate" configs/hanging.ini --steps 1 --quiet --frames "$FR" --csv "$T/fr.csv" --obj "$T/fr.obj" 2>"$T/err"
ok "also: simulate --quiet --frames printed: $(cat "$T/err")" test ! -s "$T/err"

# ---- item 15: --shard I/N is parsed with range checks (the low 32 bits of 4294967299 are 3) ----
for bad in 2/4294967299 4294967298/4294967299 2/3x +2/3 " 2/3" 2/-3 0/3 4/3 2/1000001; do
  "$B/topology" --smoke --list-cells --shard "$bad" --out "$T/shard.csv" >/dev/null 2>"$T/err"
  ok "item 15: --shard '$bad' accepted" test $? -ne 0
  ok "item 15: --shard '$bad': no message: $(cat "$T/err")" grep -q "expected I/N" "$T/err"
done
"$B/topology" --smoke --list-cells --shard 2/3 --out "$T/shard.csv" >/dev/null 2>"$T/err"
ok "item 15: --shard 2/3 refused: $(cat "$T/err")" test $? -eq 0

# ---- item 17: readme-config.sh never empties the config reference ----
cp docs/config.md "$T/R.md"
scripts/readme-config.sh "$T/no-such-simulate" "$T/R.md" >/dev/null 2>"$T/err"
ok "item 17: readme-config.sh with a missing simulate exited 0" test $? -ne 0
ok "item 17: readme-config.sh with a missing simulate changed the README" cmp -s docs/config.md "$T/R.md"
printf '#!/bin/sh\nexit 3\n' >"$T/bad-simulate" && chmod +x "$T/bad-simulate"
scripts/readme-config.sh "$T/bad-simulate" "$T/R.md" >/dev/null 2>"$T/err"
ok "item 17: readme-config.sh with a failing simulate exited 0" test $? -ne 0
ok "item 17: readme-config.sh with a failing simulate changed the README" cmp -s docs/config.md "$T/R.md"
scripts/readme-config.sh "$B/simulate" "$T/R.md" 2>"$T/err"
ok "item 17: readme-config.sh with simulate failed: $(cat "$T/err")" test $? -eq 0
ok "item 17: the regenerated reference has no key table" grep -q '^| `mesh.type`' "$T/R.md"

# ---- item 18: calibrate-hints on a bad first line: its own message, no traceback ----
for first in "shard" "shard x y z balanced" "" "shard 1 1 ten balanced"; do
  { echo "$first"; echo "tables -"; echo "0 1 0 fix 0 2 0.5"; } >"$T/bad.cells"
  scripts/calibrate-hints "$T/bad.cells" >"$T/cal.out" 2>&1
  ok "item 18: calibrate-hints on first line '$first' exited 0 or 1" test $? -eq 2
  ok "item 18: calibrate-hints on first line '$first': a traceback" sh -c "! grep -q Traceback '$T/cal.out'"
  ok "item 18: calibrate-hints on first line '$first': no message of its own" grep -q '^calibrate-hints: ' "$T/cal.out"
done
{ echo "shard 1 1 1 balanced"; echo "tables -"; echo "0 1 0 fix zero 2 0.5"; } >"$T/bad.cells"
scripts/calibrate-hints "$T/bad.cells" >"$T/cal.out" 2>&1
ok "item 18: calibrate-hints on a non-numeric cell line: a traceback" sh -c "! grep -q Traceback '$T/cal.out'"

# ---- Also: jacobi-nl's not_spd says why; movies.sh's messages name MOVIES_WORK, not its link folder ----
"$B/simulate" configs/hanging.ini --quiet --steps 2 --set integrator.method=jacobi-nl --set integrator.diagonal=exact \
  --set integrator.definiteness=none --set scene.initial_scale=0.5 --csv "$T/j.csv" --obj "$T/j.obj" 2>"$T/err"
ok "also: jacobi-nl exact/none on a compressed cloth did not stop not_spd: $(cat "$T/err")" grep -q 'step 1: not_spd' "$T/err"
ok "also: jacobi-nl's not_spd says nothing of why: $(cat "$T/err")" grep -q 'not positive definite.*integrator.definiteness = none' "$T/err"
if command -v gnuplot >/dev/null 2>&1; then
  W="$T/movies work"
  BUILD=$B MOVIES_ONLY=explicit_blowup MOVIES_STEPS=25 MOVIES_WORK="$W" PLOTS_OUT="$T/movies out" scripts/movies.sh >"$T/movies.out" 2>&1
  ok "also: movies.sh failed: $(tail -n 3 "$T/movies.out")" test $? -eq 0
  ok "also: movies.sh reports no divergence of explicit_blowup (a) in 25 steps" grep -q 'explicit_blowup (a): simulate: step' "$T/movies.out"
  ok "also: movies.sh names its link folder: $(grep cbmovies "$T/movies.out" | head -c 300)" sh -c "! grep -q cbmovies '$T/movies.out'"
  ok "also: movies.sh does not name MOVIES_WORK" grep -qF "$W/explicit_blowup/a.csv" "$T/movies.out"
fi

[ $fail = 0 ] && echo "hardening: ok ($n checks)"
exit $fail
