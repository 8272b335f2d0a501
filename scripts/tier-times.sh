#!/bin/sh
# Measures the test tiers and writes their times into docs/testing.md between the
# tier-times markers (so the documented times are measured, never typed):
#   make clean, then make test     (a fresh build: compile and tests)
#   make test again                (once built)
#   and with --all: make check-all, make experiments QUICK=1, and their sum
#   with make test (what .ci/run runs). The quick experiments run in a
#   scratch copy of the repository (its build included, results/ and
#   plots/out/ left out): the last full run's results/, plots and REPORT.md
#   stay as they are.
# The per-experiment times of the built make test's --smoke runs
# (tests/experiments.sh prints them) go in a second table.
#   scripts/tier-times.sh [--all] [README]
# Extra make arguments in TIER_MAKE_ARGS (e.g. WERROR=1). Removes build/.
set -eu
cd "$(dirname "$0")/.."
all=0
[ "${1:-}" = --all ] && { all=1; shift; }
readme=${1:-docs/testing.md}
args=${TIER_MAKE_ARGS:-}
T=$(mktemp -d "${TMPDIR:-/tmp}/cbtiers.XXXXXX")
load=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)
trap 'rm -rf "$T"' EXIT INT TERM

# timed NAME COMMAND...: runs it with its output in $T/NAME.log; its wall time in s to $T/NAME.s
timed() {
  name=$1
  shift
  echo "tier-times: $*" >&2
  t0=$(date +%s.%N)
  "$@" >"$T/$name.log" 2>&1 || { echo "tier-times: '$*' failed:" >&2; tail -n 30 "$T/$name.log" >&2; exit 1; }
  awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f\n", b - a }' >"$T/$name.s"
}
fmt() { awk -v s="$1" 'BEGIN { if (s < 60) printf "%.0f s", s; else printf "%d min %02.0f s", int(s / 60), s - 60 * int(s / 60) }'; }

# shellcheck disable=SC2086 # TIER_MAKE_ARGS is a list of make arguments
{
  timed clean make clean
  timed fresh make test $args
  timed built make test $args
  if [ $all = 1 ]; then
    timed checkall make check-all $args
    # a copy with the build (times kept, so nothing recompiles) but without the results
    mkdir "$T/repo"
    tar -cf - --exclude=./results --exclude=./plots/out --exclude=./build/san --exclude=./build/fuzz \
      --exclude=./build/coverage . | tar -C "$T/repo" -xf - || { echo "tier-times: cannot copy the repository to $T/repo" >&2; exit 1; }
    echo "tier-times: the quick experiments run in a scratch copy ($T/repo); results/ and plots/out/ are not touched" >&2
    timed quick make -C "$T/repo" experiments QUICK=1 $args
  fi
}

rev=$(git rev-parse --short=12 HEAD)
[ -z "$(git status --porcelain --untracked-files=no)" ] || rev="$rev (dirty)"
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -n 1)
{
  echo "<!-- tier-times:begin -->"
  echo "Measured by \`scripts/tier-times.sh$([ $all = 1 ] && echo " --all")\`${args:+ (make arguments: \`$args\`)} on $(date -u +%Y-%m-%d) at $rev,"
  echo "${cpu:-unknown CPU}, $(getconf _NPROCESSORS_ONLN) cores, load average $load before the first run (Debian packages already installed):"
  echo
  echo "| command | wall time |"
  echo "|---|---|"
  echo "| \`make clean && make test\` (fresh build) | $(fmt "$(cat "$T/fresh.s")") |"
  echo "| \`make test\` (built) | $(fmt "$(cat "$T/built.s")") |"
  if [ $all = 1 ]; then
    echo "| \`make check-all\` (after \`make test\`) | $(fmt "$(cat "$T/checkall.s")") |"
    echo "| \`make experiments QUICK=1\` | $(fmt "$(cat "$T/quick.s")") |"
    echo "| \`.ci/run\` (the three, from a fresh build) | $(fmt "$(awk -v a="$(cat "$T/fresh.s")" -v b="$(cat "$T/checkall.s")" -v c="$(cat "$T/quick.s")" 'BEGIN { print a + b + c }')") |"
  fi
  echo
  echo "The \`--smoke\` runs in the built \`make test\`:"
  echo
  echo "| experiment | wall time |"
  echo "|---|---|"
  sed -n 's/^experiments: \([a-z0-9_]*\) --smoke \([0-9.]*\) s$/\1 \2/p' "$T/built.log" | while read -r x t; do
    # an experiment whose code never reads e.smoke runs its --quick sweep for --smoke
    if grep -q 'smoke' experiments/"$x"/*.c; then echo "| $x | $t s |"; else echo "| $x | $t s (no smoke cells yet: its --quick run) |"; fi
  done
  echo "<!-- tier-times:end -->"
} >"$T/block.md"
cat "$T/block.md"
if grep -q '^<!-- tier-times:begin -->$' "$readme"; then
  awk -v block="$T/block.md" '
    $0 == "<!-- tier-times:begin -->" { while ((getline l < block) > 0) print l; skip = 1; next }
    $0 == "<!-- tier-times:end -->" { skip = 0; next }
    !skip { print }' "$readme" >"$readme.tmp.$$" && mv "$readme.tmp.$$" "$readme"
  echo "tier-times: $readme updated" >&2
else
  echo "tier-times: no tier-times markers in $readme; the table is above" >&2
fi
