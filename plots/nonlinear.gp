# Figures of the nonlinear experiment (claims J3 panel a, W1, P1; error against run time).
# Every name (rho values, scenes, methods) is read from the CSVs, never typed here.
load 'plots/common.gp'
set datafile columnheaders
main  = results.'/nonlinear.csv'
spec  = results.'/nonlinear_spectrum.csv'
trace = results.'/nonlinear_w1_trace.csv'
p1    = results.'/nonlinear_p1.csv'
et    = results.'/nonlinear_error_time.csv'
is(col, v) = strcol(col) eq v
# the i-th distinct value of column c (1-based field number) of a CSV, in file order
nth(file, c, i) = system(sprintf("awk -F, '!/^#/ && !h++ {next} !/^#/ && !s[$%d]++ {print $%d}' %s | sed -n '%dp'", c, c, file, i))
count(file, c) = int(system(sprintf("awk -F, '!/^#/ && !h++ {next} !/^#/ && !s[$%d]++ {n++} END {print n+0}' %s", c, file)))
# A 'using' expression is evaluated at every row, so the names it compares with
# are read into an array first (nth() there would run awk once a row).

# ---- J3 (a): the lab's iteration, per rho ------------------------------------------
set output out.'/nonlinear_j3_rho.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1400,600 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1400,600 enhanced font 'sans,10' }
set multiplot layout 1, 2 title "J3 (a): the GAMES103 lab's Chebyshev-Jacobi on F(x), 32 iterations a frame (lab scene, damping 0.99)"
set title 'median relative |grad F| after the 32 iterations of each frame (red: the run diverged)'
set xlabel 'rho given'
set ylabel 'median |grad F(x_{32})| / |grad F(xhat)|'
set logscale y
set format y '10^{%T}'
set key top left
set xtics rotate by -30
plot main using 0:(column('diverged') == 0 ? column('median_rel_grad') : NaN):xtic(strcol('rho_given')) with linespoints pt 7 lw 2 title 'converged run', \
     main using 0:(column('diverged') != 0 ? column('median_rel_grad') : NaN) with points pt 5 ps 1.6 lc rgb '#d62728' title 'diverged (median before)'
unset logscale y; set format y '%g'; set xtics norotate
set title 'the iteration''s linearised rho(I - D^{-1}A(x)) along each run (Lanczos, exact Hessian)'
set xlabel 'frame'
set ylabel 'rho(I - D^{-1} A)'
set logscale x
set key outside right
nr = count(spec, 2)
array rhos[nr]
do for [i = 1:nr] { rhos[i] = nth(spec, 2, i) }
plot for [i = 1:nr] spec using (is('rho_given', rhos[i]) ? column('frame') : NaN):'rho_lin' with linespoints pt 7 ps 0.6 \
       title 'rho = '.rhos[i], \
     1 with lines dt 2 lc 'black' title 'rho = 1'
unset logscale x
unset multiplot
set terminal pop

# ---- W1: relative |grad F| against iteration, plain and accelerated -----------------
set output out.'/nonlinear_w1.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1400,500 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1400,500 enhanced font 'sans,10' }
nsc = count(trace, 1)
nme = count(trace, 3)
array mw[nme]
do for [m = 1:nme] { mw[m] = nth(trace, 3, m) }
set multiplot layout 1, nsc title "W1: relative |grad F| per iteration of one step, plain against Chebyshev-accelerated (dashed: 1e-2, 1e-4)"
set logscale xy
set format y '10^{%T}'
set xlabel 'iteration'
set ylabel '|grad F(x_k)| / |grad F(xhat)|'
set key bottom left
do for [s = 1:nsc] {
  sc = nth(trace, 1, s)
  set title sc noenhanced
  plot for [m = 1:nme] trace using (is('scene', sc) && is('method', mw[m]) && column('iter') > 0 ? column('iter') : NaN):'rel_grad' \
         with lines lw 2 title mw[m] noenhanced, \
       1e-2 with lines dt 2 lc 'gray' notitle, 1e-4 with lines dt 2 lc 'gray' notitle
}
unset multiplot
set terminal pop
unset logscale; set format y '%g'

# ---- error against run time, every implicit method on the same steps -----------------
set output out.'/nonlinear_error_time.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1400,650 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1400,650 enhanced font 'sans,10' }
nsc = count(et, 1)
nme = count(et, 3)
array me[nme]
do for [m = 1:nme] { me[m] = nth(et, 3, m) }
set multiplot layout 1, nsc title "Error against run time: one implicit step, every method at 1, 2, 4, ... iterations"
set logscale xy
set format xy '10^{%T}'
set xlabel 'wall time of the step, ms'
set ylabel 'step error |x - x^*|_M / |x^* - x_0|_M'
set key outside right
do for [s = 1:nsc] {
  sc = nth(et, 1, s)
  set title sc noenhanced
  plot for [m = 1:nme] et using (is('scene', sc) && is('method', me[m]) && column('step_error') > 0 ? column('wall_ms') : NaN):'step_error' \
         with linespoints pt (m % 7 + 1) ps 0.8 lw 1.5 title me[m] noenhanced
}
unset multiplot
set terminal pop

# ---- P1: time per frame and step error, pd (10 iterations) against Newton -----------
set output out.'/nonlinear_p1.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1200,500 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1200,500 enhanced font 'sans,10' }
nsc = count(p1, 1)
nme = count(p1, 4)
array mp[nme]
do for [m = 1:nme] { mp[m] = nth(p1, 4, m) }
set multiplot layout 1, nsc title "P1: projective dynamics (10 iterations) against converged Newton and Baraff-Witkin, 81^2 cloth, per frame"
set logscale xy
set format xy '10^{%T}'
set xlabel 'wall time per frame, ms'
set ylabel 'step error against the converged step'
set key top right
do for [s = 1:nsc] {
  sc = nth(p1, 1, s)
  set title sc noenhanced
  plot for [m = 1:nme] p1 using (is('scene', sc) && is('method', mp[m]) ? column('wall_ms') : NaN):'step_error' \
         with points pt 7 ps 1.4 title mp[m] noenhanced
}
unset multiplot
set terminal pop
