#!/bin/sh
# End-to-end checks of build/report: the report says what produced it (run
# kind, revision, date, threads, machine, from the CSVs' provenance), and its
# figure links are relative to where the report is written.
# The report runs on a smoke CSV (--smoke, make test's tier): its verdicts
# mean nothing, but the report must say it is a smoke run and not crash.
# With SMOKE_DIR=<dir> (make check: every experiment's smoke CSVs), it takes
# definiteness.csv from there instead of running definiteness --smoke itself,
# and reports on the whole folder: every claim checker reads a smoke CSV.
# Run from the repository root (make check does: BUILD=<dir> tests/report.sh).
set -u
B=${BUILD:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbreport.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
fail=0 n=0
has() { desc=$1; shift; n=$((n + 1)); grep -Fq -- "$1" "$2" || { echo "report: FAIL: $desc ('$1' not in $2)"; fail=1; }; }
hasnot() { desc=$1; shift; n=$((n + 1)); ! grep -Fq -- "$1" "$2" || { echo "report: FAIL: $desc ('$1' in $2)"; fail=1; }; }

mkdir -p "$T/res" "$T/plots"
if [ -n "${SMOKE_DIR:-}" ]; then
  cp "$SMOKE_DIR/definiteness.csv" "$T/res/definiteness.csv" || { echo "report: FAIL: no $SMOKE_DIR/definiteness.csv"; exit 1; }
  for f in "$SMOKE_DIR"/definiteness_*.csv; do [ -f "$f" ] && cp "$f" "$T/res/"; done
else
  CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/definiteness" --smoke --out "$T/res/definiteness.csv" >/dev/null 2>"$T/def.err" ||
    { echo "report: FAIL: definiteness --smoke:"; cat "$T/def.err"; exit 1; }
fi
n=$((n + 1)); grep -q '^# smoke: 1$' "$T/res/definiteness.csv" || { echo "report: FAIL: the smoke CSV lacks '# smoke: 1'"; fail=1; }
"$B/report" --results "$T/res" --plots "$T/plots" --out "$T/out/sub/R.md" 2>"$T/rep.err" ||
  { echo "report: FAIL: build/report:"; cat "$T/rep.err"; exit 1; }
R=$T/out/sub/R.md
rev=$(sed -n 's/^# git_revision: //p' "$T/res/definiteness.csv" | head -n 1)
cpu=$(sed -n 's/^# cpu: //p' "$T/res/definiteness.csv" | head -n 1)
has "a provenance section" "## What produced this report" "$R"
has "the run kind" "| definiteness | smoke (\`--smoke\`, make test) | $rev |" "$R"
has "the machine" "| $cpu | $(getconf _NPROCESSORS_ONLN) |" "$R"
kernel=$(sed -n 's/^# blas_kernel: //p' "$T/res/definiteness.csv" | head -n 1)
choice=$(sed -n 's/^# blas_kernel_choice: //p' "$T/res/definiteness.csv" | head -n 1)
case $choice in # how the report words it (claims/origin.c), from the CSV: any of them, whatever this machine did
chosen*) how=chosen ;;
"set by the environment"*) how=environment ;;
*"; refused "*) how="detected; better one refused" ;;
detected*) how=detected ;;
*) how="?" ;;
esac
has "the OpenBLAS kernel and how it came to run" "| $kernel ($how" "$R"
has "the summary line" "This is a **smoke** run of 1 experiment (the others were not run)" "$R"
has "a smoke run's verdicts decide nothing" "its verdicts decide nothing about the claims" "$R"
# the same CSV without its smoke line is a quick run's
grep -v '^# smoke: 1$' "$T/res/definiteness.csv" > "$T/res/d.csv" && mv "$T/res/d.csv" "$T/res/definiteness.csv"
"$B/report" --results "$T/res" --plots "$T/plots" --out "$T/Rq.md" 2>/dev/null
has "a quick run" "| definiteness | quick (\`QUICK=1\`) | $rev |" "$T/Rq.md"
has "a quick run's summary" "This is a **quick** run of 1 experiment" "$T/Rq.md"
hasnot "a quick run is not called smoke" "its verdicts decide nothing" "$T/Rq.md"
has "figure links relative to the report's folder" "](../../plots/definiteness_h1.png)" "$R"
hasnot "no link into the default plots folder" "plots/out/" "$R"
# a full run's CSV from a dirty tree is reported as such
sed 's/^# quick: 1$/# quick: 0/; s/^\(# git_revision: [0-9a-f]*\) (clean)$/\1 (dirty)/' "$T/res/definiteness.csv" > "$T/res/d.csv" && mv "$T/res/d.csv" "$T/res/definiteness.csv"
sed 's/^# blas_kernel: .*/# blas_kernel: SkylakeX/; s/^# blas_kernel_choice: .*/# blas_kernel_choice: chosen SkylakeX; the detected Prescott is a fallback; self-test passed: .../' \
  "$T/res/definiteness.csv" > "$T/res/d.csv" && mv "$T/res/d.csv" "$T/res/definiteness.csv"
"$B/report" --results "$T/res" --plots "$T/plots" --out "$T/R2.md" 2>/dev/null
has "a chosen kernel" "| SkylakeX (chosen) |" "$T/R2.md"
has "a full run" "This is a **full** run of 1 experiment" "$T/R2.md"
has "a dirty tree" "uncommitted changes" "$T/R2.md"
has "links from the results folder itself" "](plots/definiteness_h1.png)" "$T/R2.md"
# --fill: marked blocks are regenerated from the same data, idempotently
printf 'intro\n<!-- report:claim-short H1 -->\nstale text\n<!-- /report -->\nmiddle `<!-- report:not-a-marker -->` inline\n<!-- report:claim H2 -->\n<!-- /report -->\n<!-- report:verdicts -->\nold table\n<!-- /report -->\n<!-- report:runtimes -->\n<!-- /report -->\nend\n' > "$T/doc.md"
printf 'wall_s: 65.5\nquick: 1\n' > "$T/res/definiteness.runtime"
"$B/report" --results "$T/res" --fill-only --fill "$T/doc.md" 2>"$T/fill.err" || { echo "report: FAIL: --fill:"; cat "$T/fill.err"; fail=1; }
h1=$(sed -n 's/^\*\*H1: \([a-z ]*\)\.\*\*.*/\1/p' "$T/doc.md")
has "fill: the claim-short block has H1's verdict" "| H1 | $h1 |" "$T/doc.md"
hasnot "fill: the stale text is gone" "stale text" "$T/doc.md"
hasnot "fill: the old table is gone" "old table" "$T/doc.md"
has "fill: an inline mention is not a marker" 'middle `<!-- report:not-a-marker -->` inline' "$T/doc.md"
has "fill: the text around the blocks is kept" "intro" "$T/doc.md"
has "fill: the full claim block has the numbers" "**H2: " "$T/doc.md"
has "fill: the verdict block ends with the count line" "undecided (within the spread)**" "$T/doc.md"
has "the report counts the verdicts" "claims: " "$R"
has "fill: the run-time table" "| definiteness | full | 1 min 06 s |" "$T/doc.md"
cp "$T/doc.md" "$T/doc1.md"
"$B/report" --results "$T/res" --fill-only --fill "$T/doc.md" 2>/dev/null
n=$((n + 1)); cmp -s "$T/doc.md" "$T/doc1.md" || { echo "report: FAIL: fill is not idempotent"; fail=1; }
printf 'a\n<!-- report:claim Z9 -->\n<!-- /report -->\n' > "$T/bad.md"
cp "$T/bad.md" "$T/bad.keep"
"$B/report" --results "$T/res" --fill-only --fill "$T/bad.md" 2>"$T/bad.err"
rc=$?
n=$((n + 1)); [ $rc -eq 1 ] || { echo "report: FAIL: an unknown claim marker gave exit $rc, not 1"; fail=1; }
has "fill: the bad marker's location" "bad.md:2: report marker 'claim Z9': no claim Z9" "$T/bad.err"
n=$((n + 1)); cmp -s "$T/bad.md" "$T/bad.keep" || { echo "report: FAIL: a failed fill changed the file"; fail=1; }
# issue 21, defect 4: a block without its end marker may not run on into the next block
printf 'a\n<!-- report:runtimes -->\nhand-written text\n<!-- report:verdicts -->\nold\n<!-- /report -->\nz\n' > "$T/noend.md"
cp "$T/noend.md" "$T/noend.keep"
"$B/report" --results "$T/res" --fill-only --fill "$T/noend.md" 2>"$T/noend.err"
rc=$?
n=$((n + 1)); [ $rc -eq 1 ] || { echo "report: FAIL: a missing end marker gave exit $rc, not 1"; fail=1; }
has "fill: the missing end marker's line" "noend.md:2: report marker with no <!-- /report --> before the next marker (line 4)" "$T/noend.err"
n=$((n + 1)); cmp -s "$T/noend.md" "$T/noend.keep" || { echo "report: FAIL: a fill with a missing end marker changed the file"; fail=1; }
# issue 21, defect 11: a NUL byte is refused, not a cut at the NUL
printf 'a\n<!-- report:runtimes -->\n<!-- /report -->\nx\000y\nmore\n' > "$T/nul.md"
cp "$T/nul.md" "$T/nul.keep"
"$B/report" --results "$T/res" --fill-only --fill "$T/nul.md" 2>"$T/nul.err"
rc=$?
n=$((n + 1)); [ $rc -eq 1 ] || { echo "report: FAIL: a NUL byte gave exit $rc, not 1"; fail=1; }
has "fill: the NUL byte's line" "nul.md:4: NUL byte" "$T/nul.err"
n=$((n + 1)); cmp -s "$T/nul.md" "$T/nul.keep" || { echo "report: FAIL: a fill of a file with a NUL byte changed it"; fail=1; }
# every marker in README.md and docs/ is one the report knows
for doc in README.md docs/*.md docs/experiments/*.md; do
  cp "$doc" "$T/copy.md"
  n=$((n + 1))
  "$B/report" --results "$T/empty" --fill-only --fill "$T/copy.md" 2>"$T/copy.err" || { echo "report: FAIL: $doc:"; cat "$T/copy.err"; fail=1; }
done
# every figure a plot script draws backs a claim: the report's verdict table lists it
# (except the bench's figures, bench_*: they illustrate README's Performance section, not a claim)
mkdir -p "$T/empty"
"$B/report" --results "$T/empty" --out "$T/all.md" 2>/dev/null
for name in $(sed -n "s/.*set output out\.'\/\([a-z0-9_]*\)\.'\.ext.*/\1/p" plots/*.gp | sort -u); do
  case $name in bench_*) continue ;; esac
  has "figure $name.png is referenced by a claim" "\`$name.png\`" "$T/all.md"
done
if [ -n "${SMOKE_DIR:-}" ]; then
  "$B/report" --results "$SMOKE_DIR" --plots "$T/plots" --out "$T/smoke.md" 2>"$T/smoke.err" ||
    { echo "report: FAIL: build/report on $SMOKE_DIR:"; cat "$T/smoke.err"; fail=1; }
  has "the smoke folder's report: a smoke run" "This is a **smoke** run of " "$T/smoke.md"
  hasnot "the smoke folder's report: every experiment's CSV is there" "the others were not run" "$T/smoke.md"
fi
[ $fail = 0 ] && echo "report: ok ($n checks)"
exit $fail
