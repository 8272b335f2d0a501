#!/bin/sh
# make movies: animated GIFs (gnuplot's `gif animate` terminal) of two runs of
# one scene side by side, from `simulate --frames` OBJ sequences.
# Each movie is one line of MOVIES below:
#   name|claim|steps|every|config|title A|--set args A|title B|--set args B
# and becomes plots/out/movie_<claim>_<name>.gif; build/report embeds every
# plots/out/movie_<claim>_*.gif next to that claim in results/REPORT.md.
# The explicit run keeps going past the energy bound (diverge_ratio 1e12) so
# the blow-up is seen, not only detected; a side that stops holds its last
# frame, and its title says why.
set -u
B=${BUILD:-build}
OUT=${PLOTS_OUT:-plots/out}
WORK=${MOVIES_WORK:-results/movies}
SIM=$B/simulate
[ -x "$SIM" ] || { echo "movies: $SIM not built (run: make movies)" >&2; exit 1; }
command -v gnuplot >/dev/null 2>&1 || { echo "movies: gnuplot not found (make deps installs gnuplot-nox)" >&2; exit 1; }
mkdir -p "$OUT" "$WORK"

MOVIES='explicit_blowup|E1|60|1|configs/hanging.ini|explicit (symplectic Euler), dt = 12 ms|integrator.method=explicit integrator.dt=0.012 integrator.diverge_ratio=1e12|implicit Euler (Newton), dt = 12 ms|integrator.method=newton integrator.dt=0.012
bw_vs_newton|I3|60|1|configs/hanging.ini|Baraff-Witkin (one Newton iteration), k = 1e6 N/m|material.stretch_k=1e6 integrator.max_iters=1|converged Newton, k = 1e6 N/m|material.stretch_k=1e6 integrator.max_iters=50'

# triangles of an OBJ as closed polylines, one blank line after each (splot with lines)
AWK=$WORK/obj2lines.awk
cat > "$AWK" <<'AWKEOF'
/^v / { n++; x[n] = $2; y[n] = $3; z[n] = $4 }
/^f / {
  for (k = 2; k <= 4; k++) { split($k, c, "/"); i = c[1] < 0 ? n + 1 + c[1] : c[1]; print x[i], y[i], z[i] }
  split($2, c, "/"); i = c[1] < 0 ? n + 1 + c[1] : c[1]; print x[i], y[i], z[i]; print ""
}
AWKEOF

status=0
echo "$MOVIES" | while IFS='|' read -r name claim steps every config ta sa tb sb; do
  [ -n "$name" ] || continue
  d=$WORK/$name
  rm -rf "$d"
  mkdir -p "$d/a" "$d/b"
  for side in a b; do
    if [ $side = a ]; then sets=$sa; else sets=$sb; fi
    args=""
    for kv in $sets; do args="$args --set $kv"; done
    # shellcheck disable=SC2086
    CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$SIM" "$config" $args --steps "$steps" --every "$every" --quiet \
      --frames "$d/$side" --csv "$d/$side.csv" --obj "$d/$side.obj" 2>"$d/$side.err"
    rc=$?
    [ $rc -le 4 ] || { echo "movies: $name ($side): simulate failed:" >&2; cat "$d/$side.err" >&2; status=1; continue; }
    [ $rc -eq 0 ] || echo "movies: $name ($side): $(tail -n 1 "$d/$side.err")"
  done
  # the view: the rest mesh's bounding box, widened, so a blow-up leaves the frame
  first=$d/b/frame_000000.obj
  [ -f "$first" ] || { echo "movies: $name: no frames" >&2; status=1; continue; }
  range=$(awk '/^v /{for(a=2;a<=4;a++){if(!(a in lo)||$a<lo[a])lo[a]=$a; if(!(a in hi)||$a>hi[a])hi[a]=$a}}
    END{m=0; for(a=2;a<=4;a++) if(hi[a]-lo[a]>m) m=hi[a]-lo[a]; for(a=2;a<=4;a++){c=(lo[a]+hi[a])/2; printf "%g:%g ", c-0.8*m, c+0.8*m}}' "$first")
  set -- $range
  gp=$d/movie.gp
  {
    echo "set terminal gif animate delay 6 size 960,480 font ',10' noenhanced"
    echo "set output '$OUT/movie_${claim}_${name}.gif.tmp'"
    echo "set xrange [$1]; set yrange [$3]; set zrange [$2]"
    echo "set view 65, 30; unset key; set ticslevel 0; set xlabel 'x'; set ylabel 'z'; set zlabel 'y'"
    n=0
    for f in "$d"/b/frame_*.obj; do
      step=$(basename "$f" .obj | sed 's/frame_0*//'); [ -n "$step" ] || step=0
      fa=$d/a/$(basename "$f")
      # side a may have stopped (diverged): hold its last frame, and say so
      if [ -f "$fa" ]; then note=""; else fa=$(ls "$d"/a/frame_*.obj | tail -n 1); note=" (stopped: $(sed -n 's/^simulate: step \([0-9]*\): \([a-z_]*\).*/\2 at step \1/p' "$d/a.err" | head -n 1))"; fi
      echo "set multiplot layout 1,2 title sprintf('%s, step %d', '$name', $step)"
      echo "set title \"$ta$note\"; splot '< awk -f $AWK $fa' using 1:3:2 with lines lc rgb '#c03030'"
      echo "set title \"$tb\"; splot '< awk -f $AWK $f' using 1:3:2 with lines lc rgb '#2050a0'"
      echo "unset multiplot"
      n=$((n + 1))
    done
    echo "set output"
  } > "$gp"
  if gnuplot "$gp" 2>"$d/gnuplot.log" && [ -s "$OUT/movie_${claim}_${name}.gif.tmp" ]; then
    mv "$OUT/movie_${claim}_${name}.gif.tmp" "$OUT/movie_${claim}_${name}.gif"
    echo "movies: $OUT/movie_${claim}_${name}.gif ($(ls "$d"/b/frame_*.obj | wc -l) frames)"
  else
    echo "movies: $name: gnuplot failed:" >&2; cat "$d/gnuplot.log" >&2; rm -f "$OUT/movie_${claim}_${name}.gif.tmp"; status=1
  fi
done
exit $status
