#!/bin/sh
# make movies: animated GIFs (gnuplot's `gif animate` terminal) of two runs of
# one scene side by side, from `simulate --frames` OBJ sequences.
# Each movie is one line of MOVIES below:
#   name|claim|steps|every|config|title A|--set args A|title B|--set args B[|options]
# and becomes plots/out/movie_<claim>_<name>.gif; build/report embeds every
# plots/out/movie_<claim>_*.gif next to that claim in results/REPORT.md.
# The --set args are separated by whitespace, so a value holds none (scene.pins
# takes `halfspace,1,0,1,0` as well as `halfspace 1 0 1 0`). options, also
# separated by whitespace, all optional:
#   view=ROT_X,ROT_Z[,SCALE]  gnuplot's `set view` for both panels (default
#                     65,30; ROT_X = 90 looks horizontally, the scene's y up;
#                     ROT_Z = 0 looks along +z with +x to the right)
#   view_a=..., view_b=...  the same for one panel (e.g. each along its own
#                     fold line)
#   fit               the view box is the bounding box of every frame of both
#                     runs and of the sphere, widened by 10% (default: the rest
#                     mesh's, widened by 60%, so that a blow-up leaves the frame)
#   clock             each panel's title adds its run's compute time so far
#                     (the sum of the CSV's wall_ms up to that frame)
# The cloth is drawn as shaded triangles with their edges (side A red, side B
# blue); a scene with a collider (collider.type in the CSV's config_effective
# line) has its sphere drawn too, grey, at c + t v, at 0.95 r so that the
# cloth resting on its contact shell (r + thickness) is not cut by the sphere's
# flat facets. The explicit run keeps going past the energy bound
# (diverge_ratio 1e12) so the blow-up is seen, not only detected; a side that
# stops holds its last frame, and its title says why.
# Environment: PLOTS_OUT (default plots/out), MOVIES_WORK (the runs' frames,
# default results/movies), BUILD; for tests, MOVIES_ONLY=NAME renders that
# movie alone and MOVIES_STEPS=N shortens every run to N steps.
set -u
B=${BUILD:-build}
OUT=${PLOTS_OUT:-plots/out}
WORK=${MOVIES_WORK:-results/movies}
SIM=$B/simulate
[ -x "$SIM" ] || { echo "movies: $SIM not built (run: make movies)" >&2; exit 1; }
command -v gnuplot >/dev/null 2>&1 || { echo "movies: gnuplot not found (make deps installs gnuplot-nox)" >&2; exit 1; }
mkdir -p "$OUT" "$WORK" || exit 1
# gnuplot code and its '< awk ...' commands are written with paths in them:
# they get symbolic links of fixed, plain names in a temporary folder, never
# the user's paths (a space, a quote or a $ in PLOTS_OUT or MOVIES_WORK)
abs() { case $1 in /*) printf '%s' "$1" ;; *) printf '%s/%s' "$(pwd)" "$1" ;; esac; }
REAL_OUT=$(abs "$OUT")
safe=$(mktemp -d "${TMPDIR:-/tmp}/cbmovies.XXXXXX") || exit 1
trap 'rm -rf "$safe"' EXIT
trap 'exit 1' INT TERM HUP
ln -s "$REAL_OUT" "$safe/out" && ln -s "$(abs "$WORK")" "$safe/work" || exit 1
OUT=$safe/out
WORK=$safe/work
REAL_WORK=$(abs "${MOVIES_WORK:-results/movies}")
# a message of simulate or gnuplot names the link folder: say the user's paths instead
shown() {
  L=$safe RW=$REAL_WORK RO=$REAL_OUT awk '
    function sub_all(s, from, to,   i, r) {
      r = ""
      while ((i = index(s, from)) > 0) { r = r substr(s, 1, i - 1) to; s = substr(s, i + length(from)) }
      return r s
    }
    { print sub_all(sub_all($0, ENVIRON["L"] "/work", ENVIRON["RW"]), ENVIRON["L"] "/out", ENVIRON["RO"]) }'
}

# E1, I3: the lab cloth (hanging.ini). B2: the sphere drape (drape.ini) at 16^2,
# one of bending's two B2 resolutions (32^2 takes a minute for the dihedral
# side alone); the titles carry each run's compute time. L1: locking_fold.ini,
# the locking experiment's fold scene at k = 1e5 N/m, pinned on one side of its
# `cross` fold line (A, x + z = 0, across the grid's diagonals) and of its
# `diagonal` one (B, x = z, along them); each panel looks along its own fold
# line from 15 deg off it, so the fold reads as the angle between the halves.
MOVIES='explicit_blowup|E1|60|1|configs/hanging.ini|explicit (symplectic Euler), dt = 12 ms|integrator.method=explicit integrator.dt=0.012 integrator.diverge_ratio=1e12|implicit Euler (Newton), dt = 12 ms|integrator.method=newton integrator.dt=0.012
bw_vs_newton|I3|60|1|configs/hanging.ini|Baraff-Witkin (one Newton iteration), k = 1e6 N/m|material.stretch_k=1e6 integrator.max_iters=1|converged Newton, k = 1e6 N/m|material.stretch_k=1e6 integrator.max_iters=50
drape|B2|45|1|configs/drape.ini|dihedral (hinge) bending, 16x16|mesh.n=16 material.bend=dihedral|quadratic bending (Bergou 2006), 16x16|mesh.n=16 material.bend=quadratic|view=70,30 fit clock
fold|L1|60|1|configs/locking_fold.ini|springs 1e5 N/m, no bending; fold across the diagonals: locks|scene.pins=halfspace,1,0,1,0|springs 1e5 N/m, no bending; fold along the diagonals: folds|scene.pins=halfspace,1,0,-1,0|view_a=80,60 view_b=80,330 fit'

# triangles of an OBJ inside the view box (box = "x0 x1 y0 y1 z0 z1") for pm3d:
# each a degenerate quad (two scans: p1 p2, p3 p3), x y z and a palette value
# base + shade (two-sided, a fixed light from above). pm3d cannot clip a
# polygon at the box, so with out=1 the triangles that leave it are printed
# instead, as closed polylines (splot with lines, which gnuplot clips).
AWK=$WORK/obj2pm3d.awk
cat > "$AWK" <<'AWKEOF'
BEGIN { lx = 0.3; ly = 0.85; lz = 0.45; ln = sqrt(lx * lx + ly * ly + lz * lz); lx /= ln; ly /= ln; lz /= ln
  split(box, b, " ") }
/^v / { n++; x[n] = $2; y[n] = $3; z[n] = $4 }
/^f / {
  for (k = 2; k <= 4; k++) { split($k, c, "/"); t[k - 1] = c[1] < 0 ? n + 1 + c[1] : c[1] }
  inside = 1
  for (k = 1; k <= 3; k++) {
    i = t[k]
    if (!(x[i] >= b[1] && x[i] <= b[2] && y[i] >= b[3] && y[i] <= b[4] && z[i] >= b[5] && z[i] <= b[6])) inside = 0
  }
  if (out) {
    if (!inside) { for (k = 1; k <= 4; k++) { i = t[(k - 1) % 3 + 1]; print x[i], y[i], z[i] }; print "" }
    next
  }
  if (!inside) next
  ax = x[t[2]] - x[t[1]]; ay = y[t[2]] - y[t[1]]; az = z[t[2]] - z[t[1]]
  bx = x[t[3]] - x[t[1]]; by = y[t[3]] - y[t[1]]; bz = z[t[3]] - z[t[1]]
  nx = ay * bz - az * by; ny = az * bx - ax * bz; nz = ax * by - ay * bx; nn = sqrt(nx * nx + ny * ny + nz * nz)
  s = nn > 0 ? (nx * lx + ny * ly + nz * lz) / nn : 1; if (s < 0) s = -s
  if (s != s) s = 1
  s = base + 0.2 + 0.78 * s
  print x[t[1]], y[t[1]], z[t[1]], s; print x[t[2]], y[t[2]], z[t[2]], s; print ""
  print x[t[3]], y[t[3]], z[t[3]], s; print x[t[3]], y[t[3]], z[t[3]], s; print ""; print ""
}
AWKEOF
# the sphere (centre cx cy cz + t (vx vy vz), drawn radius 0.95 r) as one pm3d
# surface, shaded 0..1 (grey) by the same light
SPHERE=$WORK/sphere.awk
cat > "$SPHERE" <<'AWKEOF'
BEGIN {
  cx += t * vx; cy += t * vy; cz += t * vz; r *= 0.95
  pi = atan2(0, -1); lx = 0.3; ly = 0.85; lz = 0.45; ln = sqrt(lx * lx + ly * ly + lz * lz); lx /= ln; ly /= ln; lz /= ln
  nu = 32; nv = 16
  for (j = 0; j <= nv; j++) {
    v = -pi / 2 + pi * j / nv
    for (i = 0; i <= nu; i++) {
      u = 2 * pi * i / nu; nx = cos(u) * cos(v); ny = sin(v); nz = sin(u) * cos(v)
      s = nx * lx + ny * ly + nz * lz; if (s < 0) s = 0
      print cx + r * nx, cy + r * ny, cz + r * nz, 0.25 + 0.7 * s
    }
    print ""
  }
}
AWKEOF
# "step t_s compute_s" per row of a simulate CSV (columns found by name)
STEPS=$WORK/steps.awk
cat > "$STEPS" <<'AWKEOF'
BEGIN { FS = "," }
/^#/ { next }
!h { for (k = 1; k <= NF; k++) { if ($k == "step") cs = k; if ($k == "t_s") ct = k; if ($k == "wall_ms") cw = k }; h = 1; next }
cs { w += cw ? $cw : 0; print $cs, ct ? $ct : 0, cw ? w / 1000 : -1 }
AWKEOF
# the collider of a simulate CSV's config_effective line: "type cx cy cz r vx vy vz"
COLLIDER=$WORK/collider.awk
cat > "$COLLIDER" <<'AWKEOF'
/^# config_effective:/ {
  key = ""
  for (k = 3; k <= NF; k++) {
    if (index($k, "=")) { key = substr($k, 1, index($k, "=") - 1); val[key] = substr($k, index($k, "=") + 1) }
    else if (key != "") val[key] = val[key] " " $k
  }
  split(val["collider.centre"], c, " "); split(val["collider.velocity"], v, " ")
  print val["collider.type"], c[1] + 0, c[2] + 0, c[3] + 0, val["collider.radius"] + 0, v[1] + 0, v[2] + 0, v[3] + 0
  exit
}
AWKEOF

status=0
echo "$MOVIES" | { while IFS='|' read -r name claim steps every config ta sa tb sb opts; do
  [ -n "$name" ] || continue
  [ -z "${MOVIES_ONLY:-}" ] || [ "$name" = "$MOVIES_ONLY" ] || continue
  steps=${MOVIES_STEPS:-$steps}
  view_a="65, 30"
  view_b=$view_a
  clock=0
  fit=0
  for o in ${opts:-}; do
    case $o in
      view=*) view_a=$(echo "${o#*=}" | sed 's/,/, /g'); view_b=$view_a ;;
      view_a=*) view_a=$(echo "${o#*=}" | sed 's/,/, /g') ;;
      view_b=*) view_b=$(echo "${o#*=}" | sed 's/,/, /g') ;;
      clock) clock=1 ;;
      fit) fit=1 ;;
      *) echo "movies: $name: unknown option '$o' (view=, view_a=, view_b=ROT_X,ROT_Z[,SCALE]; fit; clock)" >&2; status=1 ;;
    esac
  done
  d=$WORK/$name
  rm -rf "$d"
  mkdir -p "$d/a" "$d/b"
  failed=0
  for side in a b; do
    if [ $side = a ]; then sets=$sa; else sets=$sb; fi
    args=""
    for kv in $sets; do args="$args --set $kv"; done
    # shellcheck disable=SC2086
    CB_QUIET=1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 "$SIM" "$config" $args --steps "$steps" --every "$every" --quiet \
      --frames "$d/$side" --csv "$d/$side.csv" --obj "$d/$side.obj" 2>"$d/$side.err"
    rc=$?
    [ $rc -le 4 ] || { echo "movies: $name ($side): simulate failed:" >&2; shown <"$d/$side.err" >&2; status=1; failed=1; continue; }
    [ $rc -eq 0 ] || echo "movies: $name ($side): $(tail -n 1 "$d/$side.err" | shown)"
    awk -f "$STEPS" "$d/$side.csv" > "$d/$side.steps"
    awk -f "$COLLIDER" "$d/$side.csv" > "$d/$side.collider"
  done
  [ $failed = 0 ] || continue
  # frames are listed from the side with more of them; the other holds its last
  na=$(ls "$d"/a/frame_*.obj 2>/dev/null | wc -l); nb=$(ls "$d"/b/frame_*.obj 2>/dev/null | wc -l)
  if [ "$na" -gt "$nb" ]; then lead=a; else lead=b; fi
  first=$(ls "$d"/$lead/frame_*.obj 2>/dev/null | head -n 1)
  [ -n "$first" ] || { echo "movies: $name: no frames" >&2; status=1; continue; }
  # the view box: a cube about the rest mesh (or, with fit, everything drawn)
  if [ $fit = 1 ]; then boxed="$d/a/frame_*.obj $d/b/frame_*.obj $d/a.collider $d/b.collider"; widen=0.55
  else boxed=$first; widen=0.8; fi
  # shellcheck disable=SC2086 # $boxed: globs and several files
  range=$(awk -v widen=$widen '
    function grow(a, l, h) { if (!(a in lo) || l < lo[a]) lo[a] = l; if (!(a in hi) || h > hi[a]) hi[a] = h }
    FILENAME ~ /collider$/ { if ($1 != "none" && NF == 8) for (a = 2; a <= 4; a++) grow(a, $a - $5, $a + $5); next }
    /^v / { for (a = 2; a <= 4; a++) grow(a, $a, $a) }
    END{m=0; for(a=2;a<=4;a++) if(hi[a]-lo[a]>m) m=hi[a]-lo[a]; for(a=2;a<=4;a++){c=(lo[a]+hi[a])/2; printf "%g:%g ", c-widen*m, c+widen*m}}' \
    $boxed)
  # shellcheck disable=SC2086 # "x0:x1 y0:y1 z0:z1" into $1 $2 $3
  set -- $range
  box=$(echo "$range" | tr ':' ' ')
  gp=$d/movie.gp
  {
    echo "set terminal gif animate delay 6 size 960,480 font ',10' noenhanced"
    echo "set output '$OUT/movie_${claim}_${name}.gif.tmp'"
    echo "set xrange [$1]; set yrange [$3]; set zrange [$2]"
    echo "unset key; set ticslevel 0; set xlabel 'x'; set ylabel 'z'; set zlabel 'y'"
    echo "set pm3d depthorder border lc rgb '#303030' lw 0.5"
    # palette: 0..1 the sphere (grey), 1..2 side A (red), 2..3 side B (blue)
    echo "set palette defined (0 '#404040', 1 '#f4f4f4', 1 '#5a1010', 2 '#ffb0a8', 2 '#0c2050', 3 '#b0c8ff')"
    echo "set cbrange [0:3]; unset colorbox"
    n=0
    for f in "$d"/$lead/frame_*.obj; do
      fn=$(basename "$f")
      step=$(basename "$f" .obj | sed 's/frame_0*//'); [ -n "$step" ] || step=0
      t=$(awk -v s="$step" '$1 == s { print $2; exit }' "$d/$lead.steps")
      echo "set multiplot layout 1,2 title sprintf('%s, step %d, t = %.2f s', '$name', $step, ${t:-0})"
      for side in a b; do
        if [ $side = a ]; then title=$ta; base=1; view=$view_a; else title=$tb; base=2; view=$view_b; fi
        fs=$d/$side/$fn
        note=""
        # a side that stopped (diverged) holds its last frame, and says so
        if [ ! -f "$fs" ]; then
          fs=$(ls "$d"/$side/frame_*.obj | tail -n 1)
          note=" (stopped: $(sed -n 's/^simulate: step \([0-9]*\): \([a-z_]*\).*/\2 at step \1/p' "$d/$side.err" | head -n 1))"
        fi
        sstep=$(basename "$fs" .obj | sed 's/frame_0*//'); [ -n "$sstep" ] || sstep=0
        if [ $clock = 1 ]; then
          w=$(awk -v s="$sstep" '$1 == s { print $3; exit }' "$d/$side.steps")
          [ -n "$w" ] && [ "$w" != "-1" ] && note="$note, compute $(printf '%.2f' "$w") s"
        fi
        plot="'< awk -v base=$base -v box=\"$box\" -f $AWK $fs' using 1:3:2:4 with pm3d"
        plot="$plot, '< awk -v out=1 -v box=\"$box\" -f $AWK $fs' using 1:3:2 with lines lc rgb '$([ $side = a ] && echo '#c03030' || echo '#2050a0')'"
        # shellcheck disable=SC2046 # "type cx cy cz r vx vy vz" into $1..$8
        set -- $(cat "$d/$side.collider")
        if [ $# -eq 8 ] && [ "$1" != none ]; then
          st=$(awk -v s="$sstep" '$1 == s { print $2; exit }' "$d/$side.steps")
          sph=$d/$side/sphere_$fn.dat
          awk -v cx="$2" -v cy="$3" -v cz="$4" -v r="$5" -v vx="$6" -v vy="$7" -v vz="$8" -v t="${st:-0}" \
            -f "$SPHERE" > "$sph"
          plot="'$sph' using 1:3:2:4 with pm3d, $plot"
        fi
        echo "set view $view; set title \"$title$note\"; splot $plot"
      done
      echo "unset multiplot"
      n=$((n + 1))
    done
    echo "set output"
  } > "$gp"
  if gnuplot "$gp" 2>"$d/gnuplot.log" && [ -s "$OUT/movie_${claim}_${name}.gif.tmp" ]; then
    mv "$OUT/movie_${claim}_${name}.gif.tmp" "$OUT/movie_${claim}_${name}.gif"
    echo "movies: $REAL_OUT/movie_${claim}_${name}.gif ($n frames)"
  else
    echo "movies: $name: gnuplot failed:" >&2; shown <"$d/gnuplot.log" >&2; rm -f "$OUT/movie_${claim}_${name}.gif.tmp"; status=1
  fi
done
exit $status; }
