#!/bin/sh
# make reference: keeps the last full run (results/*.csv, the side CSVs, the
# .runtime files and REPORT.md; no images: make plots draws them) as the
# reference run of this CPU, results/reference/<cpu>/, which make compare
# reads and which is committed. Refuses a quick or smoke run, a run whose
# CSVs come from more than one git revision, and a missing REPORT.md.
#   scripts/store-reference.sh [RESULTS_DIR]
set -u
src=${1:-results}
root=${REFERENCE_ROOT:-results/reference}
[ -s "$src/REPORT.md" ] || { echo "store-reference: no $src/REPORT.md: run make experiments first" >&2; exit 1; }
set -- "$src"/*.csv
[ -f "$1" ] || { echo "store-reference: no CSV in $src/" >&2; exit 1; }
if grep -lq -e '^# quick: 1' -e '^# smoke: 1' "$@" 2>/dev/null; then
  echo "store-reference: $src/ holds a quick or smoke run ($(grep -l -e '^# quick: 1' -e '^# smoke: 1' "$@" | head -n 1)); only a full run is a reference" >&2
  exit 1
fi
revs=$(sed -n 's/^# git_revision: //p' "$@" | sort -u)
[ "$(printf '%s\n' "$revs" | grep -c .)" = 1 ] || { echo "store-reference: the CSVs come from several revisions:" $revs >&2; exit 1; }
cpu=$(sed -n 's/^# cpu: //p' "$1" | head -n 1)
key=$(printf '%s' "${cpu:-unknown}" | tr -c 'A-Za-z0-9._-' '_')
dst=$root/$key
tmp=$root/.$key.tmp.$$
rm -rf "$tmp" && mkdir -p "$tmp" || exit 1
trap 'rm -rf "$tmp"' EXIT INT TERM
cp "$src"/*.csv "$src"/REPORT.md "$tmp/" || exit 1
for f in "$src"/*.runtime; do [ -f "$f" ] && cp "$f" "$tmp/"; done
rm -rf "$dst.old" && { [ ! -d "$dst" ] || mv "$dst" "$dst.old"; } && mv "$tmp" "$dst" && rm -rf "$dst.old" || exit 1
echo "store-reference: $dst ($(du -sh "$dst" | cut -f1), revision $revs)"
