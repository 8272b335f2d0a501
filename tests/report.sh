#!/bin/sh
# End-to-end checks of build/report: the report says what produced it (run
# kind, revision, date, threads, machine, from the CSVs' provenance), and its
# figure links are relative to where the report is written.
# Run from the repository root (make check does: BUILD=<dir> tests/report.sh).
set -u
B=${BUILD:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbreport.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
fail=0 n=0
has() { desc=$1; shift; n=$((n + 1)); grep -Fq -- "$1" "$2" || { echo "report: FAIL: $desc ('$1' not in $2)"; fail=1; }; }
hasnot() { desc=$1; shift; n=$((n + 1)); ! grep -Fq -- "$1" "$2" || { echo "report: FAIL: $desc ('$1' in $2)"; fail=1; }; }

mkdir -p "$T/res" "$T/plots"
CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$B/definiteness" --quick --out "$T/res/definiteness.csv" >/dev/null 2>"$T/def.err" ||
  { echo "report: FAIL: definiteness --quick:"; cat "$T/def.err"; exit 1; }
"$B/report" --results "$T/res" --plots "$T/plots" --out "$T/out/sub/R.md" 2>"$T/rep.err" ||
  { echo "report: FAIL: build/report:"; cat "$T/rep.err"; exit 1; }
R=$T/out/sub/R.md
rev=$(sed -n 's/^# git_revision: //p' "$T/res/definiteness.csv" | head -n 1)
cpu=$(sed -n 's/^# cpu: //p' "$T/res/definiteness.csv" | head -n 1)
has "a provenance section" "## What produced this report" "$R"
has "the run kind" "| definiteness | quick (\`QUICK=1\`) | $rev |" "$R"
has "the machine" "| $cpu | $(getconf _NPROCESSORS_ONLN) |" "$R"
has "the summary line" "This is a **quick** run of 1 experiment (the others were not run)" "$R"
has "figure links relative to the report's folder" "](../../plots/definiteness_h1.png)" "$R"
hasnot "no link into the default plots folder" "plots/out/" "$R"
# a full run's CSV from a dirty tree is reported as such
sed 's/^# quick: 1$/# quick: 0/; s/^\(# git_revision: [0-9a-f]*\) (clean)$/\1 (dirty)/' "$T/res/definiteness.csv" > "$T/res/d.csv" && mv "$T/res/d.csv" "$T/res/definiteness.csv"
"$B/report" --results "$T/res" --plots "$T/plots" --out "$T/R2.md" 2>/dev/null
has "a full run" "This is a **full** run of 1 experiment" "$T/R2.md"
has "a dirty tree" "uncommitted changes" "$T/R2.md"
has "links from the results folder itself" "](plots/definiteness_h1.png)" "$T/R2.md"
[ $fail = 0 ] && echo "report: ok ($n checks)"
exit $fail
