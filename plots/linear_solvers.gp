# Figures of the linear_solvers experiment (claims J1-J4).
# Data: results/linear_solvers.csv (per iteration), _runs.csv (per run),
# _scenes.csv (spectra of D^-1 A per captured Newton matrix), _scaling.csv (J4: time to a
# manufactured solution against mesh size).
if (!exists("plots")) plots = 'plots'
load plots.'/common.gp'
set datafile columnheaders  # column('name') also in stats
main   = results.'/linear_solvers.csv'
runs   = results.'/linear_solvers_runs.csv'
scenes = results.'/linear_solvers_scenes.csv'
scaling = results.'/linear_solvers_scaling.csv'
# Every name comes from the CSV (distinct() in common.gp):
# scenes with runs, in the order they were run (lab_rest has a spectrum only)
run_scenes = distinct(runs, 'scene', 'v("sweep") == "main"')
# scenes with the full alpha sweep (down to alpha_max/10)
sweep_scenes = distinct(runs, 'scene', 'v("sweep") == "alpha" && v("alpha_over_max") != "" && v("alpha_over_max") < 0.2')
# every solver of the main sweep (the registry's order), and the iterative
# ones: those that took more than one iteration somewhere (a direct solve is one)
solvers = distinct(runs, 'solver', 'v("sweep") == "main"')
iterative = distinct(runs, 'solver', 'v("sweep") == "main" && v("iters") > 1')
direct(v) = wordpos(iterative, v) == 0
color(v) = pcolor(solvers, v)
is(col, v) = strcol(col) eq v

# ---- J1: alpha sweep, measured rate against the predicted rho(I - alpha D^-1 A) --------
set output out.'/linear_solvers_j1_alpha.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1200,900 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1200,900 enhanced font 'sans,10' }
nsw = words(sweep_scenes)
set multiplot layout (nsw > 2 ? 2 : 1), 2 title "J1: weighted Jacobi on captured Newton matrices, rate against alpha (x = alpha / (2/lambda_{max}))"
set xlabel 'alpha / (2 / lambda_{max}(D^{-1}A))'
set ylabel 'residual ratio per iteration'
set key top left
do for [i = 1:nsw] {
  s = word(sweep_scenes, i)
  set xrange [*:*]; set yrange [*:*]  # stats obeys the plot ranges
  stats scenes using (is('scene', s) ? (is('spectrum', 'dense') ? column('lmin_dense') : column('lmin_lanczos')) : NaN) nooutput
  lo = STATS_max
  stats scenes using (is('scene', s) ? (is('spectrum', 'dense') ? column('lmax_dense') : column('lmax_lanczos')) : NaN) nooutput
  hi = STATS_max
  set xrange [0:2.2]; set yrange [0:3.4]
  rho(f) = (abs(1 - 2*f*lo/hi) > abs(1 - 2*f)) ? abs(1 - 2*f*lo/hi) : abs(1 - 2*f)
  set title sprintf("%s: lambda(D^{-1}A) in [%.4g, %.4g], vanilla alpha = 1 at x = %.2f", s, lo, hi, hi/2)
  set arrow 1 from 1, graph 0 to 1, graph 1 nohead dt 2 lc 'gray'
  plot rho(x) with lines lw 2 lc 'black' title 'predicted rho(I - alpha D^{-1}A)', \
       1 with lines dt 3 lc 'gray' notitle, \
       runs using (is('scene', s) && is('solver', 'jacobi') && !is('status', 'diverged') ? column('alpha_over_max') : NaN):'rate' \
         with points pt 7 ps 1.2 lc rgb '#1f77b4' title 'measured, converging', \
       runs using (is('scene', s) && is('solver', 'jacobi') && is('status', 'diverged') ? column('alpha_over_max') : NaN):'rate' \
         with points pt 5 ps 1.2 lc rgb '#d62728' title 'measured, diverged (growth > 1e6)', \
       runs using (is('scene', s) && is('solver', 'jacobi') && column('alpha') == 1 ? column('alpha_over_max') : NaN):'rate' \
         with points pt 6 ps 3 lw 2 lc 'black' title 'vanilla alpha = 1'
  unset arrow 1
}
unset multiplot
set terminal pop
unset xrange; unset yrange

# ---- J1: all Jacobi runs, measured against predicted rate (iteration exponents) -------
set output out.'/linear_solvers_j1_rates.'.ext
set title "J1: measured asymptotic rate against predicted rho(I - alpha D^{-1}A), every Jacobi run"
set logscale xy
set format xy '10^{%T}'
set xlabel '|ln rho| predicted (GSL dense or Lanczos)'
set ylabel '|ln rate| measured (last quarter of the run)'
set key top left
# settled: the rates over the last and the previous quarter of the run agree within 5% in the exponent
settled(r, q) = q > 0 && abs(log(r) / log(q) - 1) <= 0.05
plot x with lines lc 'black' title 'measured = predicted', \
     for [pass = 0:1] runs using (is('solver', 'jacobi') && column('rate') > 0 && settled(column('rate'), column('rate_prev')) == pass ? \
       abs(log(column('rho_predicted'))) : NaN):(abs(log(column('rate')))) with points pt (pass ? 7 : 6) ps 1.1 \
       lc rgb (pass ? '#1f77b4' : '#999999') title (pass ? 'rate settled by the end of the run' : 'rate not settled (last two quarters differ > 5%)')
unset logscale; set format xy '%g'

# ---- J2: iterations and time to 1e-6 per scene and solver ----------------------------
set output out.'/linear_solvers_j2_speedup.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1200,900 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1200,900 enhanced font 'sans,10' }
nsc = words(run_scenes)
idx(s) = sum [k = 1:nsc] (word(run_scenes, k) eq s ? k : 0)
nit = words(iterative)
off(s) = -0.4 + (wordpos(iterative, s) - 0.5) * 0.8 / nit  # the iterative solvers' bars side by side
set multiplot layout 2, 1 title "J2: Jacobi against Chebyshev-Jacobi (same alpha* = 2/(lambda_{min}+lambda_{max})) to relative residual 1e-6; the other iterative solvers for context"
set style fill solid 0.8 border -1
set boxwidth 0.72 / nit
set logscale y
set xrange [0.4:nsc + 0.6]
set xtics () 
do for [k = 1:nsc] { set xtics add (word(run_scenes, k) k) }
set key top left
if (nit > 4) { set key maxrows 4 }  # more solvers: the key in columns, no taller than with four
set ylabel 'iterations to 1e-6'
set xlabel ''
set title 'iterations (missing bar: 1e-6 not reached within max\_iters)'
plot for [s in iterative] runs using (is('sweep', 'main') && is('solver', s) ? idx(strcol('scene')) + off(s) : NaN):'iters_1e6' \
       with boxes lc rgb color(s) title s
set ylabel 'wall time to 1e-6, ms'
if (nit > 4) {  # a taller key: room for it above the bars
  stats runs using (idx(strcol('scene'))):(is('sweep', 'main') ? column('wall_to_1e6_ms') : NaN) nooutput
  set yrange [*:STATS_max_y * 300]
}
set title 'wall time, including set-up (a spectral estimate such as Chebyshev''s automatic rho: the black bar)'
plot for [s in iterative] runs using (is('sweep', 'main') && is('solver', s) ? idx(strcol('scene')) + off(s) : NaN):'wall_to_1e6_ms' \
       with boxes lc rgb color(s) title s, \
     runs using (is('sweep', 'main') && column('rho_ms') > 0 ? idx(strcol('scene')) + off(strcol('solver')) : NaN):'rho_ms':(0.08) \
       with boxes fs solid 1.0 lc 'black' title 'spectral estimate (part of the set-up)'
unset multiplot
set terminal pop
unset logscale; unset xrange; unset yrange; set xtics autofreq; set style fill empty

# ---- J3: rho sweep on the lab scene --------------------------------------------------
set output out.'/linear_solvers_j3_rho.'.ext
set title "J3: Chebyshev-Jacobi on the lab scene's Newton matrix (dashed: the true rho(I - alpha D^{-1}A))"
tx(r) = -log10(1 - r)
set xlabel 'rho given  (axis: -log10(1 - rho))'
set xtics ('0.9' 1, '0.95' tx(0.95), '0.98' tx(0.98), '0.99' 2, '0.995' tx(0.995), '0.999' 3, '0.9999' 4)
set xrange [0.9:4.2]
set logscale y
set yrange [5:20000]
set ylabel 'iterations to relative residual 1e-6'
set key bottom right
alab(v) = v > 1 ? 'alpha = 1 (vanilla; true rho > 1)' : abs(v - 0.5) < 1e-9 ? 'alpha = alpha_{max}/2' : 'alpha = alpha* (Chebyshev-optimal)'
sel(k, v) = k == 0 ? (v < 1 && abs(v - 0.5) > 1e-9) : k == 1 ? abs(v - 0.5) < 1e-9 : v > 1
plot for [k = 0:1] runs using (is('scene', 'lab') && is('sweep', 'rho') && sel(k, column('alpha_over_max')) ? tx(column('rho')) : NaN):'iters_1e6' \
       with linespoints pt 7 lw 2 title (k == 0 ? 'alpha = alpha* (converging for every rho)' : 'alpha = alpha_{max}/2'), \
     for [k = 0:1] runs using (is('scene', 'lab') && is('sweep', 'rho') && sel(k, column('alpha_over_max')) ? tx(column('rho_predicted')) : NaN):(20000) \
       with impulses dt 2 lw 1.5 lc (k + 1) notitle, \
     runs using (is('scene', 'lab') && is('sweep', 'rho') && is('status', 'diverged') && column('rho') < 1 ? tx(column('rho')) : NaN):(12000) \
       with points pt 2 ps 1.5 lc 'red' title 'diverged (alpha = 1, true rho > 1: every rho given)', \
     runs using (is('scene', 'lab') && (is('sweep', 'rho_auto') || is('sweep', 'main') && is('solver', 'chebyshev')) && column('rho') < 1 ? tx(column('rho')) : NaN):'iters_1e6' \
       with points pt 3 ps 2.5 lw 2 lc 'black' title 'rho = auto (Lanczos estimate)'
unset logscale; unset xrange; unset yrange; set xtics autofreq

# ---- J4: time to error 1e-6 against a manufactured solution, against the dofs -----------
set output out.'/linear_solvers_j4_scaling.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1000,700 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1000,700 enhanced font 'sans,10' }
scale_solvers = distinct(scaling, 'solver', 'v("solver") != ""')
set title "J4: analyse + factor + solve to error |x - x*|/|x*| <= 1e-6, b = A x* (manufactured x*); open: not reached, capped time (a lower bound)"
set logscale xy
set xlabel 'dofs n'
set ylabel 'wall time, ms (median; bars: fastest and slowest repeat)'
set format y '10^{%T}'
set key top left font ',9'
# the rows of one solver are not adjacent (the table goes size by size): bars as points, lines from that solver's rows alone
plot for [v in scale_solvers] scaling using (is('solver', v) && is('status', 'ok') ? column('n_dofs') : NaN):'wall_ms':'wall_min_ms':'wall_max_ms' \
       with yerrorbars pt (v eq 'cholmod' ? 9 : 7) ps (v eq 'cholmod' ? 2 : 1) lw 1.5 lc rgb pcolor(scale_solvers, v) title v, \
     for [v in scale_solvers] '< awk -F, '."'".'/^#/ { next } !h { h = 1; print; next } $5 == "'.v.'" && $NF == "ok"'."' '".scaling."'" \
       using 'n_dofs':'wall_ms' with lines lw (v eq 'cholmod' ? 3 : 1.5) lc rgb pcolor(scale_solvers, v) notitle, \
     for [v in scale_solvers] scaling using (is('solver', v) && !is('status', 'ok') ? column('n_dofs') : NaN):'capped_wall_ms' \
       with points pt 6 ps 1.5 lc rgb pcolor(scale_solvers, v) notitle
unset logscale; set format y '%g'
set terminal pop

# ---- error against wall time on the captured Newton systems, one panel per scene -------
# (context for J4: the error here is against CHOLMOD refined once; J4 is decided on the figure above)
set output out.'/linear_solvers_j4_error_time.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1500,1100 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1500,1100 enhanced font 'sans,10' }
set multiplot layout (nsc > 6 ? 3 : 2), (nsc > 4 ? 3 : 2) title "Error |x - x*|/|x*| against wall time (set-up included) on the captured Newton systems, x* = CHOLMOD refined once (context for J4)"
set logscale xy
set xlabel 'wall time, ms'
set ylabel 'error |x - x*| / |x*|'
set yrange [1e-16:10]
set format y '10^{%T}'
set key bottom left font ',9'
do for [k = 1:nsc] {
  s = word(run_scenes, k)
  set autoscale xy
  stats scenes using (is('scene', s) ? column('n_dofs') : NaN) nooutput
  set logscale xy; set yrange [1e-16:10]
  set title sprintf('%s (%d DOFs)', s, STATS_max)
  plot for [v in solvers] main using (is('scene', s) && is('sweep', 'main') && is('solver', v) && column('wall_ms') > 0 ? column('wall_ms') : NaN):'error' \
         with linespoints pt (direct(v) ? 9 : 7) ps (direct(v) ? 2 : 0.4) lc rgb color(v) title v
}
unset multiplot
set terminal pop
