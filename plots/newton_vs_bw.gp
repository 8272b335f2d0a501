# newton_vs_bw (claims I2, I3): error against run time, the K = 1 regime map,
# Newton's convergence, trajectory error. Data: results/newton_vs_bw*.csv.
if (!exists("plots")) plots = 'plots'
load plots.'/common.gp'

main   = results.'/newton_vs_bw.csv'
pareto = results.'/newton_vs_bw_pareto.csv'
regime = results.'/newton_vs_bw_regime.csv'
i2     = results.'/newton_vs_bw_i2.csv'
traj   = results.'/newton_vs_bw_traj.csv'
dterr  = results.'/newton_vs_bw_dt.csv'

# ---- I3: step error against wall time, one panel per scene ------------------
# colour = inner solve, point shape = K; filled = no line search, open = line
# search; the black line joins the Pareto front (median time, worst error).
# Scenes, methods and inner solvers come from the CSVs (distinct() in
# common.gp): the inner solvers in the order of their inner_index, the
# methods in the order of their k_index (colours and symbols follow them).
max_index(file, col) = system("awk -F, '".AWK_HEAD."{ if (v(\"".col."\") + 0 > m) m = v(\"".col."\") + 0 } END { print m + 0 }' '".file."'") + 0
INNERS = ''
do for [i = 0:max_index(pareto, 'inner_index')] { INNERS = INNERS.distinct(pareto, 'inner_solver', sprintf('v("inner_index") == %d', i)) }
METHODS = ''
do for [i = 0:max_index(pareto, 'k_index')] { METHODS = METHODS.distinct(pareto, 'method', sprintf('v("k_index") == %d', i)) }
SCENES = distinct(pareto, 'scene', '1')
nsc = words(SCENES)
klabel(m) = m[1:8] eq 'newton_k' ? 'K = '.m[9:] : m[1:7] eq 'newton_' ? m[8:] : m
COLORS = '0x1f77b4 0xff7f0e 0x2ca02c 0xd62728 0x9467bd 0x7f7f7f 0x8c564b 0xe377c2 0x17becf 0xbcbd22'
PTS_FILLED = '7 5 9 11 13 15 3 1 2'
PTS_OPEN = '6 4 8 10 12 14 3 1 2'
inner_col(i) = word(COLORS, int(i) % words(COLORS) + 1) + 0
k_pt(k, ls) = word(ls > 0 ? PTS_OPEN : PTS_FILLED, int(k) % words(PTS_FILLED) + 1) + 0
# the first inner solver with a set-up (wall_no_setup_ms < wall_ms), drawn also without it
with_setup = distinct(pareto, 'inner_solver', 'v("wall_no_setup_ms") < v("wall_ms")')
setup_inner = ''
do for [q in INNERS] { if (setup_inner eq '' && wordpos(with_setup, q) > 0) { setup_inner = q } }
setup_index = wordpos(INNERS, setup_inner) - 1
# a panel title from the main CSV: grid and stiffness of the scene
k_label(k) = k >= 1e5 ? sprintf('10^%d', int(log10(k) + 0.5)) : sprintf('%g', k)
scene_title(s) = sprintf('%s (%d^2, k = %s N/m)', s, int(real(system(sprintf("awk -F, '%s v(\"scene\") == \"%s\" { print v(\"n\"); exit }' '%s'", AWK_HEAD, s, main)))), \
                         k_label(real(system(sprintf("awk -F, '%s v(\"scene\") == \"%s\" { print v(\"k_n_per_m\"); exit }' '%s'", AWK_HEAD, s, main)))))
finite(e) = (e == e && e < 1e300) ? e : NaN

set output out.'/newton_vs_bw_pareto.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1500,640 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1500,640 enhanced font 'sans,10' }
set multiplot title 'I3: step error against run time (one implicit Euler step, error vs converged x*)'
set logscale xy
set format y '10^{%L}'
set format x '10^{%L}'
set xlabel 'wall time per step (ms, median over start states)'
set ylabel 'step error |x - x*|_M / |x* - x^0|_M (max over states)'
set yrange [1e-12:100]
unset key
do for [s = 1:nsc] {
  sc = word(SCENES, s)
  set title scene_title(sc)
  set origin (s - 1) / (1.0 * nsc), 0.16
  set size 1 / (1.0 * nsc), 0.78
  # (common.gp reads the first row of every data source as its header: give $FRONT one)
  set print $FRONT
  print 'wall_ms,step_error_max'
  unset print
  set table $FRONT append separator comma
  plot pareto using 'wall_ms':'step_error_max' with table if (strcol('scene') eq sc && column('front_by_wall') == 1)
  unset table
  plot pareto using (strcol('scene') eq sc ? column('wall_ms') : NaN):(finite(column('step_error_max'))): \
         (k_pt(column('k_index'), column('line_search'))):(inner_col(column('inner_index'))) \
         with points pt variable ps 1.1 lc rgb variable, \
       $FRONT using 1:2 with lines lw 2 lc rgb 'black', \
       pareto using (strcol('scene') eq sc && column('inner_index') == setup_index ? column('wall_no_setup_ms') : NaN):(finite(column('step_error_max'))) \
         with points pt 1 ps 0.8 lc rgb inner_col(setup_index), \
       pareto using (strcol('scene') eq sc && column('failed') > 0 ? column('wall_ms') : NaN):(30): \
         (inner_col(column('inner_index'))) with points pt 2 ps 1.5 lw 2 lc rgb variable, \
       1e-2 with lines dt 2 lc rgb 'gray'
}
# the legend, in a strip below the panels
set origin 0, 0
set size 1, 0.15
unset border
unset tics
unset xlabel
unset ylabel
unset title
unset grid
unset logscale
set xrange [0:1]
set yrange [0:1]
set key at screen 0.5, 0.08 center center horizontal maxcols 8 font ',9' noopaque nobox
plot NaN with lines lw 2 lc rgb 'black' title 'Pareto front', \
     for [i = 1:words(INNERS)] NaN with points pt 7 lc rgb inner_col(i - 1) title word(INNERS, i) noenhanced, \
     NaN with points pt 1 lc rgb inner_col(setup_index) title setup_inner.' without set-up' noenhanced, \
     for [k = 1:words(METHODS)] NaN with points pt k_pt(k - 1, 0) lc rgb 'black' title klabel(word(METHODS, k)), \
     NaN with points pt 6 lc rgb 'black' title 'open symbol: line search', \
     NaN with points pt 2 lw 2 lc rgb 'black' title 'step failed (drawn at 30)', \
     NaN with lines dt 2 lc rgb 'gray' title 'error 1%'
set border
set tics
set grid
set xrange [*:*]
set yrange [*:*]
unset multiplot
set terminal pop
set key default
set key box opaque
set origin 0, 0
set size 1, 1
unset logscale
set format x '% g'
set format y '% g'
set yrange [*:*]
set xrange [*:*]

# ---- I3: the K = 1 regime map -----------------------------------------------
set output out.'/newton_vs_bw_regime.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1200,950 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1200,950 enhanced font 'sans,10' }
# the stretches, time steps and stiffnesses of the regime CSV (ticks: dt_index, k_index)
STRETCHES = distinct(regime, 'stretch', '1')
nst = words(STRETCHES)
set multiplot layout (nst > 4 ? int(ceil(nst / 2.0)) : 2), 2 title "I3: where Baraff-Witkin's single Newton iteration fails (colour: log_{10} of the largest one-step error;\nD = trajectory diverged, E = one-step error > 1%; lab scene from the stretched start; blank: not in this sweep)"
set xtics ()
do for [p in distinct_n(regime, 'v("dt_index") ":" v("dt_s")', '1', 1)] {
  dtv = real(pair2(p))
  eval sprintf("set xtics add ('%s' %d)", dtv < 1 ? sprintf('1/%d', int(1 / dtv + 0.5)) : sprintf('%g', dtv), int(pair1(p)))
}
set ytics ()
do for [p in distinct_n(regime, 'v("k_index") ":" v("k_n_per_m")', '1', 1)] {
  eval sprintf("set ytics add ('10^%d' %d)", int(log10(real(pair2(p))) + 0.5), int(pair1(p)))
}
nxi = max_index(regime, 'dt_index')
nyi = max_index(regime, 'k_index')
set xrange [-0.5:nxi + 0.5]
set yrange [-0.5:nyi + 0.5]
set xlabel 'time step dt (s)'
set ylabel 'spring stiffness k (N/m)'
set cblabel 'log_{10} one-step error'
set cbrange [-8:0]
set palette defined (-8 '#1a9850', -4 '#d9ef8b', -2 '#fee08b', -1 '#f46d43', 0 '#a50026')
unset key
set grid front
lg(e) = (e == e && e > 0) ? (log10(e) > 0 ? 0 : log10(e)) : 0
do for [a = 1:nst] {
  str = real(word(STRETCHES, a))
  set title sprintf('initial stretch %gx', str)
  plot regime using (abs(column('stretch') - str) < 1e-9 ? column('dt_index') : NaN):'k_index': \
         (column('dt_index') - 0.5):(column('dt_index') + 0.5):(column('k_index') - 0.5):(column('k_index') + 0.5): \
         (column('first_diverged_step') >= 0 ? 0 : lg(column('step_error_max'))) \
         with boxxy fs solid 1.0 lc palette, \
       regime using (abs(column('stretch') - str) < 1e-9 ? column('dt_index') : NaN):'k_index': \
         (column('first_diverged_step') >= 0 ? 'D' : column('k1_fails') > 0 ? 'E' : '') \
         with labels font ',14' tc rgb 'black'
}
unset multiplot
set terminal pop
set xtics autofreq
set ytics autofreq
set xrange [*:*]
set yrange [*:*]
unset cbrange
set key

# ---- I2: |grad F| per Newton iteration --------------------------------------
set output out.'/newton_vs_bw_convergence.'.ext
set title "I2: Newton's convergence on the stretched hanging cloth (initial scale 1.5, k = 8000 N/m, dt = 1/30 s)"
set logscale y
set format y '10^{%L}'
set xlabel 'Newton iteration'
set ylabel 'relative |{/Symbol \321}F| = |{/Symbol \321}F(x^{(k)})| / |{/Symbol \321}F(x^{(0)})|'
set yrange [1e-16:1e7]
set xrange [0:*]
set key inside top right font ',9'
array SHOW[3] = [0, 2, 4]
run(def, ls, st) = (strcol('definiteness') eq def && column('line_search') == ls && column('step') == st)
plot for [j = 1:3] i2 using (run('exact_or_shift', 1, SHOW[j]) ? column('iter') : NaN):'rel_grad' \
       with linespoints lw 2 pt 7 ps 0.7 lc j title sprintf('Newton, exact Hessian (shifted where A is indefinite) + line search, step %d', SHOW[j]), \
     for [j = 1:3] i2 using (run('drop', 1, SHOW[j]) ? column('iter') : NaN):'rel_grad' \
       with linespoints lw 1 dt 2 pt 6 ps 0.6 lc j title sprintf("Newton with the lecture's drop fix + line search, step %d", SHOW[j]), \
     1e-11 with lines lw 2 dt 4 lc rgb '#404040' title 'order estimates use |{/Symbol \321}F| above this line (10^{-11})'
unset logscale
set format y '% g'
set yrange [*:*]
set xrange [*:*]

# ---- trajectories: position error against the converged trajectory ---------
set output out.'/newton_vs_bw_trajectory.'.ext
set title 'I3: 2 s trajectories of the lab scene (dt = 1/30 s) against the converged trajectory at the same dt'
set logscale y
set format y '10^{%L}'
set xlabel 'time t (s)'
set ylabel 'RMS position error |x - x_{ref}|_M / M^{1/2} (m)'
set yrange [1e-12:1e4]
# two key columns in the empty top decades (short titles: a wider key ran off the figure)
set key inside top left vertical maxrows 5 font ',9'
# the trajectories without line search, from the CSV ('reference' is the converged one):
# with the first inner solver (the direct one) coloured by K, solid; with the others by inner solver, dashed
TCOLS_K = '0x9400d3 0x009e73 0x56b4e9 0xe69f00 0xd4c000 0x0072b2 0x8c564b 0xe377c2'
TCOLS_I = '0x000000 0xe51e10 0x7f7f7f 0x17becf 0xbcbd22 0x1f77b4 0xff7f0e'
tr(m, inn, ls) = (strcol('method') eq m && strcol('inner_solver') eq inn && column('line_search') == ls)
TPAIRS = distinct_n(traj, 'v("method") ":" v("inner_solver")', 'v("line_search") == 0 && v("method") != "reference"', 1)
ntr = words(TPAIRS)
TM(j) = pair1(word(TPAIRS, j))
TI(j) = pair2(word(TPAIRS, j))
direct(j) = wordpos(INNERS, TI(j)) == 1
TCOL(j) = direct(j) ? word(TCOLS_K, (wordpos(METHODS, TM(j)) - 1) % words(TCOLS_K) + 1) + 0 \
                    : word(TCOLS_I, (wordpos(INNERS, TI(j)) - 1) % words(TCOLS_I) + 1) + 0
TDASH(j) = direct(j) ? 1 : 2
TT(j) = klabel(TM(j)).(TM(j) eq 'newton_k1' ? ' (Baraff-Witkin)' : '').', '.TI(j)
plot for [j = 1:ntr] traj using (tr(TM(j), TI(j), 0) && column('step') > 0 ? column('t_s') : NaN):(finite(column('pos_error_m'))) \
       with lines lw 2 lc rgb TCOL(j) dashtype TDASH(j) title TT(j) noenhanced, \
     dterr using 't_s':'pos_error_m' with lines lw 3 dt 2 lc rgb 'black' title 'time-discretisation error (dt vs dt/16)'
unset logscale
set format y '% g'
set yrange [*:*]
set key default
set key box opaque

# ---- trajectories: energy --------------------------------------------------
set output out.'/newton_vs_bw_energy.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 900,800 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 900,800 enhanced font 'sans,10' }
set multiplot layout 2,1 title 'I3: energy along the 2 s lab trajectories (dt = 1/30 s)'
set title 'energy drift E(t) - E(0): the numerical damping of implicit Euler'
set xlabel 'time t (s)'
set ylabel 'E(t) - E(0) (J)'
set key inside bottom left font ',9'
plot traj using (strcol('method') eq 'reference' ? column('t_s') : NaN):'energy_drift_j' with lines lw 4 lc rgb 'black' title 'converged (reference)', \
     traj using (tr(TM(1), TI(1), 0) ? column('t_s') : NaN):'energy_drift_j' with lines lw 2 lc rgb TCOL(1) title TT(1) noenhanced
set title 'energy difference to the converged trajectory'
set logscale y
set format y '10^{%L}'
set ylabel '|E(t) - E_{ref}(t)| (J)'
set yrange [1e-10:1e8]
set key inside top left vertical maxrows 3 font ',8'  # in the empty top decades: at the bottom it hid curves
plot for [j = 1:ntr] traj using (tr(TM(j), TI(j), 0) && column('step') > 0 ? column('t_s') : NaN): \
       (abs(column('energy_j') - column('ref_energy_j'))) with lines lw 1.5 lc rgb TCOL(j) dashtype TDASH(j) title TT(j) noenhanced
unset multiplot
set terminal pop
