#!/bin/sh
# Renders every plots/<experiment>.gp whose results/<experiment>.csv exists,
# to PNG (pngcairo) and SVG in plots/out/. Fails if gnuplot reports an error.
# Runs from any directory: the scripts are found beside this one, and every
# path handed to gnuplot is absolute (RESULTS and PLOTS_OUT relative to the
# working directory, default results/ and plots/out/ of the repository).
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
abs() { case $1 in /*) printf '%s' "$1" ;; *) printf '%s/%s' "$(pwd)" "$1" ;; esac; }
out=$(abs "${PLOTS_OUT:-$root/plots/out}")
results=$(abs "${RESULTS:-$root/results}")
plots=$root/plots
mkdir -p "$out"
status=0
for gp in "$plots"/*.gp; do
  name=$(basename "$gp" .gp)
  [ "$name" = common ] && continue
  if [ ! -f "$results/$name.csv" ]; then
    echo "plots: skip $name ($results/$name.csv not found; run its experiment)"
    continue
  fi
  for ext in png svg; do
    if ! gnuplot -e "ext='$ext'; out='$out'; results='$results'; plots='$plots'" "$gp" 2>"$out/$name.$ext.log"; then
      echo "plots: $gp failed ($ext):" >&2; cat "$out/$name.$ext.log" >&2; status=1
    elif grep -qi "warning\|error" "$out/$name.$ext.log"; then
      echo "plots: $gp ($ext) printed:" >&2; cat "$out/$name.$ext.log" >&2
    fi
    rm -f "$out/$name.$ext.log"
  done
  echo "plots: $name -> $out/$name*.png, .svg"
done
exit $status
