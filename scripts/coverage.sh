#!/bin/sh
# Line coverage of lib/ by gcov (make coverage): in a build compiled with
# --coverage (BUILD, default build/cov), runs the unit tests, tests/cli.sh
# and one --smoke run of each experiment named (every experiment when none
# is), then gcovr sums the lines of lib/ and of each layer, writes the report
# to BUILD/coverage.txt (every file, its missed lines) and BUILD/coverage.json,
# and rewrites the block of docs/testing.md between the coverage markers, so the
# figures there come from this run and are never typed. Fails when lib/core/
# covers less than COVERAGE_MIN % (default 85) of its lines.
#   BUILD=build/cov scripts/coverage.sh [EXPERIMENT...]   (README: README=...)
set -eu
cd "$(dirname "$0")/.."
B=${BUILD:-build/cov}
min=${COVERAGE_MIN:-85}
readme=${README:-docs/testing.md}
[ $# -gt 0 ] || for m in experiments/*/main.c; do set -- "$@" "$(basename "$(dirname "$m")")"; done
command -v gcovr >/dev/null || { echo "coverage: gcovr is missing (apt-get install gcovr)" >&2; exit 1; }
ls "$B"/lib/core/*.gcno >/dev/null 2>&1 || { echo "coverage: no $B/lib/core/*.gcno: build with --coverage first (make coverage)" >&2; exit 1; }

find "$B" -name '*.gcda' -delete # the counts of this run only
t0=$(date +%s)
for t in "$B"/tests/test_*; do
  case $t in *.o | *.d | *.gcno | *.gcda) continue ;; esac
  echo "coverage: $t" >&2
  CB_QUIET=1 CB_SIMULATE="$B/simulate" "$t" --jobs 2 --short-filename >/dev/null
done
BUILD=$B tests/cli.sh >/dev/null
BUILD=$B tests/experiments.sh --smoke "$B/smoke" "$@" >&2
t1=$(date +%s)

gcovr -r . --filter 'lib/' --txt "$B/coverage.txt" --json-summary "$B/coverage.json" --json-summary-pretty "$B" >/dev/null
rev=$(git rev-parse --short=12 HEAD)
[ -z "$(git status --porcelain --untracked-files=no)" ] || rev="$rev (dirty)"
st=0
python3 - "$B/coverage.json" "$B/coverage.block" "$min" "$rev" "$((t1 - t0))" "$#" <<'PY' || st=1
import json, sys, datetime
summary, out, minimum, rev, secs, nexp = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4], sys.argv[5], sys.argv[6]
files = json.load(open(summary))["files"]
def total(prefix, what="line"):
    fs = [f for f in files if f["filename"].startswith(prefix)]
    cov = sum(f[what + "_covered"] for f in fs)
    n = sum(f[what + "_total"] for f in fs)
    return cov, n, 100.0 * cov / n if n else 0.0
rows = [("lib/", "all of lib/")] + [(p, p) for p in ("lib/core/", "lib/config/", "lib/instruments/", "lib/io/")]
core = total("lib/core/")
with open(out, "w") as f:
    f.write("<!-- coverage:begin -->\n")
    f.write("Measured by `make coverage` (scripts/coverage.sh) on %s at %s: the unit tests, `tests/cli.sh` and %s "
            "`--smoke` runs, %s s in the coverage build.\n\n" % (datetime.date.today().isoformat(), rev, nexp, secs))
    f.write("| code | lines | covered | line coverage | branches | taken | branch coverage |\n|---|---|---|---|---|---|---|\n")
    for prefix, name in rows:
        cov, n, pct = total(prefix)
        bcov, bn, bpct = total(prefix, "branch")
        f.write("| %s | %d | %d | %.1f %% | %d | %d | %.1f %% |\n" % (name, n, cov, pct, bn, bcov, bpct))
    low = sorted((f for f in files if f["filename"].startswith("lib/core/") and f["line_total"]),
                 key=lambda f: f["line_covered"] / f["line_total"])
    low = [f for f in low if f["line_covered"] < f["line_total"]]
    f.write("\nThe lib/core/ files by coverage, lowest first (lines not run / lines):\n\n")
    f.write(", ".join("%s %.0f %% (%d / %d)" % (x["filename"][len("lib/core/"):], 100.0 * x["line_covered"] / x["line_total"],
                                               x["line_total"] - x["line_covered"], x["line_total"]) for x in low) + ".\n")
    f.write("<!-- coverage:end -->\n")
print("coverage: lib/ %.1f %%, lib/core/ %.1f %% (%d of %d lines)" % (total("lib/")[2], core[2], core[0], core[1]))
sys.exit(0 if core[2] >= minimum else 3)
PY
cat "$B/coverage.block"
if grep -q '^<!-- coverage:begin -->$' "$readme"; then
  awk -v block="$B/coverage.block" '
    $0 == "<!-- coverage:begin -->" { while ((getline l < block) > 0) print l; skip = 1; next }
    $0 == "<!-- coverage:end -->" { skip = 0; next }
    !skip { print }' "$readme" >"$readme.tmp.$$" && mv "$readme.tmp.$$" "$readme"
  echo "coverage: $readme updated; per-file missed lines in $B/coverage.txt" >&2
else
  echo "coverage: no coverage markers in $readme; the block is above" >&2
fi
[ $st = 0 ] || { echo "coverage: lib/core/ is under $min % of its lines" >&2; exit 1; }
