#!/bin/sh
# Regenerates docs/config.md's config reference (between the config-reference
# markers) from `simulate --help-config`, the parser's own key table.
# The reference is generated first and checked (the command ran and printed
# a table): a missing or failing simulate leaves the page as it was. The
# page is replaced atomically (a temporary file renamed over it).
#   scripts/readme-config.sh [SIMULATE [PAGE]]
set -eu
bin=${1:-build/simulate}
readme=${2:-docs/config.md}
die() { echo "readme-config: $*" >&2; exit 1; }
[ -x "$bin" ] || die "$bin: not an executable (build it: make $bin); $readme not changed"
grep -q '<!-- config-reference:begin -->' "$readme" && grep -q '<!-- config-reference:end -->' "$readme" ||
  die "$readme: no config-reference markers; not changed"
tmp=$readme.tmp.$$
ref=$readme.ref.$$
trap 'rm -f "$tmp" "$ref"' EXIT
trap 'exit 1' INT TERM HUP
"$bin" --help-config >"$ref" || die "$bin --help-config failed; $readme not changed"
grep -q '^| `' "$ref" || die "$bin --help-config printed no key table; $readme not changed"
REF=$ref awk '
  /<!-- config-reference:begin -->/ { print; while ((getline l < ENVIRON["REF"]) > 0) print l; skip = 1; next }
  /<!-- config-reference:end -->/ { skip = 0 }
  !skip { print }' "$readme" >"$tmp" || die "cannot write $tmp; $readme not changed"
mv "$tmp" "$readme"
