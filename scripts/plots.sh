#!/bin/sh
# Renders every plots/<experiment>.gp whose results/<experiment>.csv exists,
# to PNG (pngcairo) and SVG in plots/out/. Fails if gnuplot reports an error.
# Runs from any directory: the scripts are found beside this one, and every
# path handed to gnuplot is absolute (RESULTS and PLOTS_OUT relative to the
# working directory, default results/ and plots/out/ of the repository).
# The plot scripts splice those paths into gnuplot and shell code (system(),
# '< awk ...'), so they are never given the user's paths: gnuplot sees
# symbolic links of fixed, plain names in a temporary folder, whatever the
# real paths hold (spaces, quotes, $, ...).
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
abs() { case $1 in /*) printf '%s' "$1" ;; *) printf '%s/%s' "$(pwd)" "$1" ;; esac; }
real_out=$(abs "${PLOTS_OUT:-$root/plots/out}")
real_results=$(abs "${RESULTS:-$root/results}")
mkdir -p "$real_out" || exit 1
safe=$(mktemp -d "${TMPDIR:-/tmp}/cbplots.XXXXXX") || exit 1
trap 'rm -rf "$safe"' EXIT
trap 'exit 1' INT TERM HUP
ln -s "$real_out" "$safe/out" && ln -s "$real_results" "$safe/results" && ln -s "$root/plots" "$safe/plots" || exit 1
out=$safe/out
results=$safe/results
plots=$safe/plots
status=0
for gp in "$plots"/*.gp; do
  name=$(basename "$gp" .gp)
  [ "$name" = common ] && continue
  if [ ! -f "$results/$name.csv" ]; then
    echo "plots: skip $name ($real_results/$name.csv not found; run its experiment)"
    continue
  fi
  failed=0
  for ext in png svg; do
    if ! gnuplot -e "ext='$ext'; out='$out'; results='$results'; plots='$plots'" "$gp" 2>"$safe/$name.$ext.log"; then
      echo "plots: plots/$name.gp failed ($ext):" >&2; cat "$safe/$name.$ext.log" >&2; status=1; failed=1
    elif grep -qi "warning\|error" "$safe/$name.$ext.log"; then
      echo "plots: plots/$name.gp ($ext) printed:" >&2; cat "$safe/$name.$ext.log" >&2
    fi
  done
  [ $failed = 1 ] || echo "plots: $name -> $real_out/$name*.png, .svg"
done
exit $status
