# Figures of the field experiment (claims X1, X2, Q1, V1; the main figure: error against wall time).
# Every name (scenes, methods) is read from the CSVs, never typed here (method names hold spaces:
# they are walked by index, nth()).
load 'plots/common.gp'
set datafile columnheaders
main  = results.'/field.csv'
x1    = results.'/field_x1.csv'
x2    = results.'/field_x2.csv'
trace = results.'/field_tol_trace.csv'
is(col, v) = strcol(col) eq v
# the i-th distinct value of column c (1-based field number) of a CSV, in file order (rows where
# column f equals g when f > 0)
nthw(file, c, i, f, g) = system(sprintf("awk -F, '!/^#/ && !h++ {next} !/^#/ && (%d == 0 || $%d == \"%s\") && !s[$%d]++ {print $%d}' %s | sed -n '%dp'", f, f > 0 ? f : 1, g, c, c, file, i))
countw(file, c, f, g) = int(system(sprintf("awk -F, '!/^#/ && !h++ {next} !/^#/ && (%d == 0 || $%d == \"%s\") && !s[$%d]++ {n++} END {print n+0}' %s", f, f > 0 ? f : 1, g, c, file)))
nth(file, c, i) = nthw(file, c, i, 0, '')
count(file, c) = countw(file, c, 0, '')

# ---- the main figure: step error against wall time per frame, one panel per scene ----------------
ns = count(main, 1)
set output out.'/field.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1600,1100 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1600,1100 enhanced font 'sans,10' }
set multiplot layout 2, 2 title "field: one step from a start state, every method at 1, 2, 4, ... iterations (thin: every point; thick: the method's error-time front; circles: the scene's front)"
set logscale xy
set format x '10^{%T}'
set format y '10^{%T}'
set xlabel 'wall time per frame (ms)'
set ylabel 'step error |x - x*|_M / |x* - x0|_M'
set key outside right font ',8'
do for [s = 1:ns] {
  sc = nth(main, 1, s)
  nm = countw(main, 3, 1, sc)
  array mn[nm]  # the scene's method names, read once (not once per row)
  do for [m = 1:nm] { mn[m] = nthw(main, 3, m, 1, sc) }
  set title sc
  plot for [m = 1:nm] main using (is('scene', sc) && is('method', mn[m]) ? column('wall_ms') : NaN):'step_error' \
         with linespoints pt 7 ps 0.4 lw 1 lc m title mn[m] noenhanced, \
       for [m = 1:nm] main using (is('scene', sc) && is('method', mn[m]) && column('on_method_front_by_wall') == 1 ? \
         column('wall_ms') : NaN):'step_error' with lines lw 3 lc m notitle, \
       main using (is('scene', sc) && column('on_scene_front_by_wall') == 1 ? column('wall_ms') : NaN):'step_error' with points pt 6 ps 1.6 lc 'black' title 'scene front'
}
unset multiplot
set terminal pop
unset logscale xy

# ---- X1: effective stiffness at convergence (top: X1's verdict) and its approach over 1-100 iterations (bottom)
# field_x1.csv: kind 'converged' rows are at the iteration count where XPBD's constraint residual converged
# (x1.c), kind 'sweep' rows at 1-100 iterations; dt_s is column 4
set output out.'/field_x1.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1400,1000 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1400,1000 enhanced font 'sans,10' }
nx = count(x1, 1)
set multiplot layout 2, nx title 'X1: effective stiffness k_{eff}/k (static stretch against the converged static state): at convergence against dt (top), approaching it over iterations (bottom)'
set logscale xy
set format x '%g'
set format y '10^{%T}'
set key bottom right
do for [s = 1:nx] {
  sc = nth(x1, 1, s)
  set title sc.': at the iteration count where XPBD'."'".'s constraint residual converged'
  set xlabel 'dt (s)'
  set ylabel 'k_{eff} / k'
  plot x1 using (is('scene', sc) && is('method', 'xpbd') && is('kind', 'converged') ? column('dt_s') : NaN):'k_ratio' \
         with linespoints pt 7 ps 1.5 lw 2 title 'xpbd', \
       x1 using (is('scene', sc) && is('method', 'pbd') && is('kind', 'converged') ? column('dt_s') : NaN):'k_ratio' \
         with linespoints pt 4 ps 1.5 dt 2 lw 2 title 'pbd', \
       1 with lines lc 'black' dt 3 title 'k'
}
do for [s = 1:nx] {
  sc = nth(x1, 1, s)
  nd = countw(x1, 4, 1, sc)
  set title sc.': over 1-100 iterations (circles: at the converged count)'
  set xlabel 'iterations per step'
  set ylabel 'k_{eff} / k'
  plot for [d = 1:nd] x1 using (is('scene', sc) && is('method', 'xpbd') && is('kind', 'sweep') && strcol('dt_s') eq nthw(x1, 4, d, 1, sc) ? column('iters') : NaN):'k_ratio' \
         with linespoints pt 7 lw 2 lc d title sprintf('xpbd dt = %.4g', real(nthw(x1, 4, d, 1, sc))), \
       for [d = 1:nd] x1 using (is('scene', sc) && is('method', 'pbd') && is('kind', 'sweep') && strcol('dt_s') eq nthw(x1, 4, d, 1, sc) ? column('iters') : NaN):'k_ratio' \
         with linespoints pt 4 dt 2 lw 2 lc d title sprintf('pbd dt = %.4g', real(nthw(x1, 4, d, 1, sc))), \
       for [d = 1:nd] x1 using (is('scene', sc) && is('kind', 'converged') && strcol('dt_s') eq nthw(x1, 4, d, 1, sc) ? column('iters') : NaN):'k_ratio' \
         with points pt 6 ps 1.8 lc d notitle, \
       1 with lines lc 'black' dt 3 title 'k'
}
unset multiplot
set terminal pop
unset logscale xy

# ---- X2: n x 1 against 1 x n --------------------------------------------------------------------------
set output out.'/field_x2.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1400,900 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1400,900 enhanced font 'sans,10' }
n2 = count(x2, 1)
set multiplot layout n2, 3 title 'X2: XPBD n substeps x 1 iteration (nx1) against 1 step x n iterations (1xn), equal work'
set logscale x 2
set format x '%g'
set xlabel 'n'
set key top right
do for [s = 1:n2] {
  sc = nth(x2, 1, s)
  set logscale y
  set format y '10^{%T}'
  set title sc.': largest edge stretch'
  plot x2 using (is('scene', sc) && is('variant', 'nx1') ? column('n') : NaN):'max_strain' with linespoints pt 7 lw 2 title 'nx1', \
       x2 using (is('scene', sc) && is('variant', '1xn') ? column('n') : NaN):'max_strain' with linespoints pt 4 lw 2 title '1xn', \
       x2 using (is('scene', sc) ? column('n') : NaN):'ref_max_strain' with lines dt 2 lc 'black' title 'converged step'
  set title sc.': step error against the converged step'
  plot x2 using (is('scene', sc) && is('variant', 'nx1') ? column('n') : NaN):'step_error' with linespoints pt 7 lw 2 title 'nx1', \
       x2 using (is('scene', sc) && is('variant', '1xn') ? column('n') : NaN):'step_error' with linespoints pt 4 lw 2 title '1xn'
  set title sc.': wall time per frame (ms)'
  plot x2 using (is('scene', sc) && is('variant', 'nx1') ? column('n') : NaN):'wall_ms' with linespoints pt 7 lw 2 title 'nx1', \
       x2 using (is('scene', sc) && is('variant', '1xn') ? column('n') : NaN):'wall_ms' with linespoints pt 4 lw 2 title '1xn'
}
unset multiplot
set terminal pop
unset logscale xy

# ---- Q1 and V1: relative |grad F| against the traced run's time and against iterations -----------------
nt = count(trace, 1)
do for [fig = 1:2] {
  set output out.'/field_'.(fig == 1 ? 'q1' : 'v1').'.'.ext
  set terminal push
  if (ext eq 'svg') { set terminal svg size 1600,1000 dynamic enhanced font 'sans,11' background rgb 'white' } \
  else { set terminal pngcairo size 1600,1000 enhanced font 'sans,10' }
  set multiplot layout 2, nt title (fig == 1 ? 'Q1: relative |grad F| of L-BFGS, pd, pd-chebyshev and Newton' : 'V1: relative |grad F| of vbd against jacobi-nl, chebyshev-nl and pd-chebyshev')
  set logscale y
  set format y '10^{%T}'
  set key top right font ',8'
  do for [row = 1:2] {
    do for [s = 1:nt] {
      sc = nth(trace, 1, s)
      nm = countw(trace, 2, 1, sc)
      array tn[nm]  # the scene's method names, read once
      do for [m = 1:nm] { tn[m] = nthw(trace, 2, m, 1, sc) }
      set title sc
      if (row == 1) { set logscale x; set format x '10^{%T}'; set xlabel 'elapsed ms of the traced run (with the hook''s gradients)' } \
      else { unset logscale x; set format x '%g'; set xlabel 'iteration'; set logscale x; set format x '%g' }
      set ylabel '|grad F(x_k)| / |grad F(xhat)|'
      plot for [m = 1:nm] trace using (mm = tn[m], is('scene', sc) && is('method', mm) && \
             (fig == 1 ? (mm eq 'lbfgs' || mm eq 'pd' || mm eq 'pd-chebyshev auto' || mm[1:6] eq 'newton') \
                       : (mm[1:3] eq 'vbd' || mm eq 'jacobi-nl' || mm eq 'chebyshev-nl auto' || mm eq 'pd-chebyshev auto')) ? \
             (row == 1 ? column('wall_ms') : column('iter') + 1) : NaN):'rel_grad' with lines lw 2 lc m title tn[m] noenhanced
    }
  }
  unset multiplot
  set terminal pop
  unset logscale xy
}
