# Figures of explicit_stability (claims E1, E2, I1), from results/explicit_stability.csv
# and its side tables _boundary.csv and _timing.csv. Rendered by scripts/plots.sh.
if (!exists("plots")) plots = 'plots'
load plots.'/common.gp'
set datafile missing NaN  # filtered rows (NaN) do not break a series' line
main  = results.'/explicit_stability.csv'
bound = results.'/explicit_stability_boundary.csv'
tim   = results.'/explicit_stability_timing.csv'

# Half the grid step of the sweep, for the heat-map tiles (the quick sweep is coarser).
quick = system("grep -c '^# quick: 1' ".main) + 0
kf = quick ? 10**0.5 : 10**0.25
df = quick ? 10**(1.0/6) : 10**(1.0/12)
code(s) = s eq 'stable' ? 0 : s eq 'unstable' ? 1 : s eq 'diverged' ? 2 : 3
is(c, v) = strcol(c) eq v
# Every scene, method and k comes from the CSVs (distinct() in common.gp):
# the (k, dt) sweep's scenes, the boundary table's, the timed methods.
sweep_scenes = distinct(main, 'scene', 'v("kind") == "sweep" && v("method") == "explicit"')
bound_scenes = distinct(bound, 'scene', '1')
# scenes whose flat rest shape predicts another limit than the hanging state
rest_scenes = distinct(bound, 'scene', 'v("dt_crit_pred_rest_s") != "" && v("dt_crit_pred_rest_s") != "nan" && ' . \
                       '(v("dt_crit_pred_rest_s") / v("dt_crit_pred_s") - 1)^2 > 1e-12')
methods = distinct(tim, 'method', '1')
mlabel(m) = m eq 'explicit' ? 'explicit' : m eq 'newton' ? 'Newton (converged, shift)' : \
            m eq 'newton_bw' ? 'Baraff-Witkin (drop)' : m eq 'newton_bw_shift' ? 'Baraff-Witkin (shift)' : \
            m[1:7] eq 'newton_' ? 'Newton, '.m[8:].' iterations' : m eq 'chebyshev_nl' ? 'chebyshev-nl' : \
            m eq 'pd' ? 'projective dynamics' : m
mshort(m) = m eq 'explicit' ? 'explicit' : m eq 'newton' ? 'Newton' : m eq 'newton_bw' ? 'BW drop' : \
            m eq 'newton_bw_shift' ? 'BW shift' : m[1:7] eq 'newton_' ? 'Newton '.m[8:].' it.' : \
            m eq 'chebyshev_nl' ? 'chebyshev-nl' : m eq 'pd' ? 'PD' : m
families = distinct(tim, 'family', '1')
# timed against k: the timed scenes of the sweep; against resolution: the k
# values at which scenes outside the sweep (larger grids) were timed
not_sweep = ''
do for [sc in sweep_scenes] { not_sweep = not_sweep . ' && v("scene") != "' . sc . '"' }
ktim_scenes = ''
do for [sc in distinct(tim, 'scene', '1')] { if (wordpos(sweep_scenes, sc) > 0) { ktim_scenes = ktim_scenes . sc . ' ' } }
res_ks = distinct(tim, 'k_n_per_m', '1' . not_sweep)
nsw = words(sweep_scenes)
map_cols = nsw > 1 ? int(ceil(sqrt(nsw))) : 1
map_rows = int(ceil(nsw / (map_cols * 1.0)))
set palette defined (-0.5 '#2e8b57', 0.5 '#2e8b57', 0.5 '#f0a020', 1.5 '#f0a020', 1.5 '#c83232', 2.5 '#c83232', \
                     2.5 '#888888', 3.5 '#888888')
set cbrange [-0.5:3.5]
set cbtics ('stable' 0, 'unstable' 1, 'diverged' 2, 'failed' 3)
set logscale xy
set format x '10^{%T}'
set format y '10^{%T}'
set mxtics 10
set mytics 10

# ---- E1: the (k, dt) map per scene, with the predicted limit over it -------------------
set output out.'/explicit_stability_map.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1200,900 dynamic enhanced font 'sans,12' background rgb 'white' } \
else { set terminal pngcairo size 1200,900 enhanced font 'sans,11' }
set multiplot layout map_rows,map_cols title 'E1: explicit (symplectic Euler) stability map, with the predicted limit dt = 2/{/Symbol w}_{max}'
set xlabel 'spring stiffness k [N/m]'
set ylabel 'time step {/Symbol D}t [s]'
set key bottom left box opaque font ',9'
set yrange [5e-6:0.4]
set xrange [5:2e7]
do for [sc in sweep_scenes] {
  set title sc
  plot main using (is('kind','sweep') && is('method','explicit') && is('scene',sc) ? column('k_n_per_m') : NaN):(column('dt_s')): \
         (column('k_n_per_m')/kf):(column('k_n_per_m')*kf):(column('dt_s')/df):(column('dt_s')*df):(code(strcol('status'))) \
         with boxxyerror fs solid 1.0 noborder lc palette notitle, \
       bound using (is('scene',sc) ? column('k_n_per_m') : NaN):(column('dt_crit_pred_s')) with lines lw 3 lc rgb 'black' \
         title 'predicted 2/{/Symbol w}_{max} (hanging)', \
       bound using (is('scene',sc) ? column('k_n_per_m') : NaN):(column('dt_crit_pred_rest_s')) with lines lw 2 dt 2 lc rgb '#3050c0' \
         title 'predicted at the flat rest shape', \
       bound using (is('scene',sc) ? column('k_n_per_m') : NaN):(column('dt_crit_meas_s')) with points pt 7 ps 1.0 lc rgb 'white' \
         notitle, \
       bound using (is('scene',sc) ? column('k_n_per_m') : NaN):(column('dt_crit_meas_s')) with points pt 6 ps 1.0 lw 1.5 \
         lc rgb 'black' title 'measured (bisection)'
}
unset multiplot
set terminal pop
unset title
set yrange [*:*]
set xrange [*:*]

# ---- E1: measured over predicted ---------------------------------------------------
set output out.'/explicit_stability_ratio.'.ext
set title 'E1: measured critical {/Symbol D}t over the prediction 2/{/Symbol w}_{max} (target: within 15%)'
set xlabel 'spring stiffness k [N/m]'
set ylabel 'dt_{crit} measured / predicted [-]'
unset logscale y
set format y '%.2f'
set yrange [0.8:1.2]
set key bottom right
plot 0.85 with lines dt 2 lw 2 lc rgb '#c05050' title '±15%', 1.15 with lines dt 2 lw 2 lc rgb '#c05050' notitle, \
     for [sc in bound_scenes] bound using (is('scene',sc) ? column('k_n_per_m') : NaN): \
       (column('dt_crit_meas_s')/column('dt_crit_pred_s')) with linespoints lw 2 pt 7 title sc.' (hanging)', \
     for [sc in rest_scenes] bound using (is('scene',sc) ? column('k_n_per_m') : NaN): \
       (column('dt_crit_meas_s')/column('dt_crit_pred_rest_s')) with linespoints dt 2 pt 6 title sc.' (vs flat rest shape)'
set yrange [*:*]
set logscale y
set format y '10^{%T}'

# ---- E2: wall time to simulate 1 s, against k and against resolution ------------------
set output out.'/explicit_stability_cost.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1300,600 dynamic enhanced font 'sans,12' background rgb 'white' } \
else { set terminal pngcairo size 1300,600 enhanced font 'sans,11' }
set multiplot layout 1,2 title 'E2: wall time to simulate 1 s of the hanging cloth: explicit at its largest stable {/Symbol D}t against implicit at {/Symbol D}t = 1/30 s'
set key top left font ',9'
set yrange [0.05:1e6]  # the top decade stays free for the key
set title 'against stiffness'
set xlabel 'spring stiffness k [N/m]'
set ylabel 'wall time for 1 s simulated [ms]'
plot for [sc in ktim_scenes] for [m in methods] \
       tim using (is('scene',sc) && is('method',m) ? column('k_n_per_m') : NaN):(column('wall_ms_per_s')) with linespoints lw 2 \
       title sc.' '.mlabel(m)
set yrange [*:*]
set title 'against resolution: stretch family (21^2, 41^2, 81^2), bending family (11^2, 21^2, 41^2)'
set key top left font ',8'
set xlabel 'vertices n [-]'
plot for [f in families] for [kk in res_ks] for [m in methods] \
       tim using (is('family',f) && column('k_n_per_m') == kk+0 && is('method',m) ? column('n_vertices') : NaN): \
       (column('wall_ms_per_s')) with linespoints lw 2 \
       title f.sprintf(' k = %g: ', kk+0).mshort(m), \
     [300:8000] 5*(x/441.0)**1.5 with lines dt 3 lw 2 lc rgb '#606060' title 'slope n^{1.5} (reference)', \
     [100:2000] 20*(x/121.0)**2 with lines dt 4 lw 2 lc rgb '#202020' title 'slope n^2 (reference)'
unset multiplot
set terminal pop

# ---- I1: Newton's numerical damping, and its stability map ---------------------------
set output out.'/explicit_stability_damping.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1300,600 dynamic enhanced font 'sans,12' background rgb 'white' } \
else { set terminal pngcairo size 1300,600 enhanced font 'sans,11' }
set multiplot layout 1,2 title 'I1: implicit Euler (converged Newton) never diverges; its price is numerical damping'
set title 'energy lost in the first 0.1 s, per simulated second'
set xlabel 'time step {/Symbol D}t [s]'
set ylabel 'energy lost per second / initial kinetic energy [1/s]'
set key top left font ',9'
set xrange [5e-6:0.2]
# the smallest, the middle and the largest k of the sweep, on the scenes with
# at least two converged-Newton cells that measured a damping window at one of them
sweep_ks = distinct(main, 'k_n_per_m', 'v("kind") == "sweep"')
nks = words(sweep_ks)
damp_ks = word(sweep_ks, 1).' '.word(sweep_ks, (nks + 1) / 2).' '.word(sweep_ks, nks)
damp_cond = 'v("kind") == "sweep" && v("method") == "newton" && v("window_s") > 0 && v("t_mark_s") >= v("window_s") * 0.999999'
damp_scenes = ''
do for [p in distinct_n(main, 'v("scene") ":" v("k_n_per_m")', damp_cond, 2)] {
  if (wordpos(damp_ks, pair2(p)) > 0 && wordpos(damp_scenes, pair1(p)) == 0) { damp_scenes = damp_scenes . pair1(p) . ' ' }
}
plot for [sc in damp_scenes] for [kk in damp_ks] \
       main using (is('kind','sweep') && is('method','newton') && is('scene',sc) && column('k_n_per_m') == kk+0 && \
       column('window_s') > 0 && column('t_mark_s') >= column('window_s')*0.999999 ? column('dt_s') : NaN):(column('energy_loss_w')/column('kinetic0_j')) \
       with linespoints lw 2 title sprintf('%s, k = %g', sc, kk+0), \
     [1e-5:0.1] 10*x with lines dt 2 lw 2 lc rgb '#606060' title 'slope 1 (reference)'
set title 'status of every Newton cell (all scenes overlaid)'
unset key
set xlabel 'spring stiffness k [N/m]'
set ylabel 'time step {/Symbol D}t [s]'
set xrange [5:2e7]
set yrange [5e-6:0.2]
plot main using (is('kind','sweep') && is('method','newton') ? column('k_n_per_m') : NaN):(column('dt_s')): \
       (column('k_n_per_m')/kf):(column('k_n_per_m')*kf):(column('dt_s')/df):(column('dt_s')*df):(code(strcol('status'))) \
       with boxxyerror fs solid 1.0 noborder lc palette notitle
unset multiplot
set terminal pop
