#!/bin/sh
# Verdicts that hold from run to run (issue 31 §7, docs/verdicts.md): every
# claim is decided again on copies of the CSVs whose timing medians sit at an
# end of their recorded spread (build/report --stability: low, high, and
# alternating row by row). A verdict may change only to or from "undecided
# (within the spread)"; one that changes between two decided verdicts was
# decided by a median alone, and this test fails.
#   tests/spread.sh [DIR]   DIR: a folder of results CSVs (check-quick's --quick runs)
# Without DIR, only the fixture part runs. The fixture: a bending.csv whose B2
# ratio (dihedral/quadratic step time, paired repeats 1.4x, 1.78x, 1.6x)
# straddles the 1.5x band edge. Decided over the spread it is undecided and the
# check passes; decided by the median alone (--median-verdicts, the rule before
# issue 31) it flips between reproduced and partly, and the check must fail.
# Run from the repository root (BUILD=<dir>, default build).
set -u
B=${BUILD:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbspread.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
fail=0
if [ -n "${1:-}" ]; then
  "$B/report" --results "$1" --stability > "$T/quick.md" 2> "$T/quick.err"
  st=$?
  if [ $st -ne 0 ]; then
    echo "spread: FAIL: a verdict on $1 changed between decided verdicts within the recorded spread (exit $st):"
    grep -v '| yes' "$T/quick.md"; cat "$T/quick.err"; fail=1
  else
    echo "spread: $(tail -n 1 "$T/quick.md")"
  fi
fi
mkdir -p "$T/fix"
cat > "$T/fix/bending.csv" <<'CSV'
# experiment: bending
# blas_kernel: fixture
part,model,mesh,n,angle_deg,stretch,radius_m,force_n,force_total_n,energy_j,energy_ref_j,ratio,steps,newton_iters,assemble_ms,factor_ms,solve_ms,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,step_min_ms,step_max_ms,assemble_min_ms,assemble_max_ms,assemble_each_ms,factor_min_ms,factor_max_ms,factor_each_ms,solve_min_ms,solve_max_ms,solve_each_ms,kinetic_j,rms_m,contacts,indefinite,hinges,status
b2,quadratic,grid,16,,,,,,,,,30,300,1,8,0.5,10,9,11,10;9;11,3,0.9,23,1,1,1;1;1,8,8,8;8;8,0.5,0.5,0.5;0.5;0.5,0.001,,10,0,0,ok
b2,dihedral,grid,16,,,,,,,,,30,330,11.5,4,0.5,16,14,17.6,14;16;17.6,3,2.5,60,1,1,1;1;1,4,4,4;4;4,0.5,0.5,0.5;0.5;0.5,0.001,,10,100,150,ok
CSV
"$B/report" --results "$T/fix" --stability > "$T/fix.md" 2>&1
st=$?
if [ $st -ne 0 ] || ! grep -q '^| B2 | undecided (within the spread) |.*| yes |$' "$T/fix.md"; then
  echo "spread: FAIL: the fixture's B2, decided over its spread, should be undecided and hold (exit $st):"
  cat "$T/fix.md"; fail=1
fi
"$B/report" --results "$T/fix" --stability --median-verdicts > "$T/fixm.md" 2>&1
st=$?
if [ $st -ne 3 ] || ! grep -q '^| B2 | reproduced |.*partly reproduced.*changed between decided verdicts' "$T/fixm.md"; then
  echo "spread: FAIL: decided by the median alone, the fixture's B2 should flip and the check fail (exit $st, want 3):"
  cat "$T/fixm.md"; fail=1
fi
[ $fail -eq 0 ] && echo "spread: the fixture is undecided over its spread, and a median-decided verdict fails the check"
exit $fail
