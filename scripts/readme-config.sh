#!/bin/sh
# Regenerates docs/config.md's config reference (between the config-reference
# markers) from `simulate --help-config`, the parser's own key table.
set -eu
bin=${1:-build/simulate}
tmp=docs/config.md.tmp.$$
awk -v cmd="$bin --help-config" '
  /<!-- config-reference:begin -->/ { print; while ((cmd | getline l) > 0) print l; close(cmd); skip = 1; next }
  /<!-- config-reference:end -->/ { skip = 0 }
  !skip { print }' docs/config.md > "$tmp"
mv "$tmp" docs/config.md
