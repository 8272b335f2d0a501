#!/bin/sh
# make compare's test: build/report --compare on the smoke CSVs against
# themselves agrees on every claim (exit 0); against a reference altered so
# that one verdict flips (T1's edge list loses an edge), it names that claim
# as differing outside the spreads and exits 1. scripts/compare.sh picks the
# reference of this CPU, or says there is none.
# Run from the repository root (make check does: BUILD=<dir> SMOKE_DIR=<dir> tests/compare.sh).
set -u
B=${BUILD:-build}
S=${SMOKE_DIR:?SMOKE_DIR: the smoke CSVs (make check)}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbcompare.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
fail=0 n=0
ok() { desc=$1; shift; n=$((n + 1)); "$@" || { echo "compare: FAIL: $desc"; fail=1; }; }

mkdir -p "$T/ours" "$T/ref"
cp "$S"/*.csv "$T/ours/" && cp "$S"/*.csv "$T/ref/"
"$B/report" --compare "$T/ref" --results "$T/ours" >"$T/same.out" 2>"$T/same.err"
ok "a run against itself does not agree (exit $?)" test $? -eq 0
ok "a run against itself: T1 not 'same'" grep -q '^| T1 | reproduced | reproduced | same |' "$T/same.out"
ok "a run against itself: no claim differs" grep -q ' 0 differ outside them' "$T/same.out"

# the altered reference: the lecture's edge {0,1} dropped, so T1 is not reproduced there
grep -v '^edge,lecture,0,1,' "$S/topology.csv" >"$T/ref/topology.csv"
"$B/report" --compare "$T/ref" --results "$T/ours" >"$T/flip.out" 2>"$T/flip.err"
st=$?
ok "a flipped verdict exits $st, not 1" test $st -eq 1
ok "the flipped claim is not named" grep -q '^| T1 | not reproduced | reproduced | DIFFERS outside the spreads |' "$T/flip.out"
ok "T2 (unchanged data) is not 'same'" grep -q '^| T2 | reproduced | reproduced | same |' "$T/flip.out"

# a reference older than an experiment (no contact.csv, as results/reference/ before issue 34): its claims are
# "new claim, no reference", and that alone is no failure
mkdir -p "$T/old"
cp "$S"/*.csv "$T/old/" && rm -f "$T/old/contact.csv"
"$B/report" --compare "$T/old" --results "$T/ours" >"$T/old.out" 2>"$T/old.err"
ok "a reference without contact.csv exits $?, not 0" test $? -eq 0
ok "C1 against a reference without contact.csv is not 'new claim, no reference'" grep -q '^| C1 | not run | [a-z ]* | new claim, no reference |' "$T/old.out"
ok "C2 against a reference without contact.csv is not 'new claim, no reference'" grep -q '^| C2 | not run | [a-z ]* | new claim, no reference |' "$T/old.out"
n_contact=$(grep -c '^| C[0-9]* | not run | [a-z ]* | new claim, no reference |' "$T/old.out")
ok "the count line does not count the $n_contact new claims" grep -q ", $n_contact new (no reference)\." "$T/old.out"

# scripts/compare.sh: no reference for the CPU -> a clear message and exit 2
mkdir -p "$T/empty"
REFERENCE_ROOT="$T/empty" BUILD=$B scripts/compare.sh "$T/ours" >"$T/none.out" 2>&1
ok "compare.sh without a reference exits $?, not 2" test $? -eq 2
ok "compare.sh without a reference does not say so" grep -q 'no reference run' "$T/none.out"
# a reference folder of another CPU is taken when it is the only one, and said so
mkdir -p "$T/refs/Some_Other_CPU" && cp "$T/ref"/*.csv "$T/refs/Some_Other_CPU/"
REFERENCE_ROOT="$T/refs" BUILD=$B scripts/compare.sh "$T/ours" >"$T/other.out" 2>&1
ok "compare.sh against the only (altered) reference exits $?, not 1" test $? -eq 1
ok "compare.sh does not name the reference it took" grep -q 'Some_Other_CPU' "$T/other.out"

# make reference keeps full runs only
echo x >"$T/ours/REPORT.md"
REFERENCE_ROOT="$T/stored" scripts/store-reference.sh "$T/ours" >"$T/store.out" 2>&1
ok "store-reference.sh kept a smoke run as a reference (exit $?)" test $? -eq 1 -a ! -d "$T/stored"
ok "store-reference.sh does not say why it refused" grep -q 'quick or smoke run' "$T/store.out"

[ $fail = 0 ] && echo "compare: ok ($n checks)"
exit $fail
