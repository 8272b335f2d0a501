# locking (claims L1, L2, F1, S1): figures from results/locking*.csv. Every
# series name (model, mesh, fold line, method, alpha) comes from the CSV.
load 'plots/common.gp'
set key noenhanced
f = results.'/locking.csv'
fd = results.'/locking_dofs.csv'
fa = results.'/locking_aniso.csv'
fn = results.'/locking_newton.csv'
fs = results.'/locking_shape.csv'

# ---- L1: fold angle at rest against in-plane stiffness, one panel per mesh ----
meshes = distinct(f, 'mesh', '1')
models = distinct(f, 'model', '1')
folds = distinct(f, 'fold', '1')
set output out.'/locking_l1.'.ext
set multiplot layout 1, words(meshes) title "L1: fold angle at rest (90 = hanging straight down) against in-plane stiffness, bending 0\n(solid: springs, dashed: FEM; open points: the fold line runs along mesh edges; unconverged solves left out)"
set logscale x
set format x '10^{%L}'
set xlabel 'k or mu (N/m)'
set ylabel 'fold angle (deg)'
set yrange [-5:100]
set key bottom left font ',8'
do for [m in meshes] {
  set title m
  plot for [md = 1:words(models)] for [fl in folds] f using \
       (strcol('mesh') eq m && strcol('model') eq word(models, md) && strcol('fold') eq fl && strcol('status') eq 'ok' ? column('k_n_per_m') : NaN):'fold_angle_deg' \
       with linespoints dt md lw 2 pt (word(distinct(f, 'on_edges', 'v("mesh") == "'.m.'" && v("fold") == "'.fl.'"'), 1) eq '1' ? 6 : 7) \
       lc rgb pcolor(folds, fl) title word(models, md).' '.fl
}
unset multiplot
unset logscale x
set format x '%g'
set yrange [*:*]

# ---- L2: DoFs per vertex against mesh size ---------------------------------------
set output out.'/locking_l2.'.ext
set title "L2: degrees of freedom per vertex with every constraint hard (3 #variables - rank of the rigidity matrix)"
set xlabel '#vertices'
set ylabel 'DoFs per vertex'
set key top right
set yrange [0:3.3]
fams = 'regular alternating ring_disk'
# the grid rows interleave the two diagonal patterns, so each family is read
# through awk (a NaN filter in `using` would break its line at every other row)
rows(file, cond) = "< awk -F, 'function v(n) { return $ix[n] } /^#/ { next } !h { print; for (i = 1; i <= NF; i++) ix[$i] = i; h = 1; next } (".cond.") { print }' '".file."'"
famcond(fm) = fm eq 'ring_disk' ? 'v("mesh") ~ /^ring_disk/' : 'v("mesh") ~ /_'.fm.'$/'
set key center right
plot for [fm in fams] rows(fd, famcond(fm)) using 'vertices':'conforming_per_vertex' with linespoints lw 2 pt 7 lc rgb pcolor(fams, fm) title 'conforming, '.fm, \
     for [fm in fams] rows(fd, famcond(fm)) using 'vertices':'nonconforming_per_vertex' with linespoints lw 2 dt 2 pt 6 lc rgb pcolor(fams, fm) title 'nonconforming (edge midpoints), '.fm, \
     3 with lines lc rgb '#7f7f7f' dt 3 title '3'
set yrange [*:*]

# ---- F1: anisotropy of the response to non-affine loads, one panel per load ------
set output out.'/locking_f1_aniso.'.ext
afams = distinct(fa, 'family', '1')
amodels = distinct(fa, 'model', '1')
ameshes = distinct(fa, 'mesh', '1')
stats fa using 'n' nooutput
nfine = STATS_max
set multiplot layout 1, words(afams) title sprintf("F1: energy per area against the load's direction, disks at the finest level n = %.0f\n(springs solid, FEM dashed; k = mu = 1000 N/m; flat = isotropic; every level is in the report)", nfine)
set xlabel 'load direction (deg)'
set ylabel 'energy density (J/m^2)'
set xrange [-5:185]
set key top right font ',8'
do for [fm in afams] {
  set title fm
  plot for [md = 1:words(amodels)] for [m in ameshes] fa using \
       (strcol('model') eq word(amodels, md) && strcol('mesh') eq m && strcol('family') eq fm && strcol('status') eq 'ok' && column('n') == nfine ? column('dir_deg') : NaN):'energy_density_j_per_m2' \
       with linespoints dt md lw 2 pt 7 lc rgb pcolor(ameshes, m) title word(amodels, md).', '.m
}
unset multiplot
set xrange [*:*]

# ---- F1: one Newton step, error against wall time ---------------------------------
set output out.'/locking_f1_newton.'.ext
methods = distinct(fn, 'model', '1')
set title "F1: one implicit Euler step of the lab cloth (first of three runs): relative |grad F| against wall time"
set xlabel 'wall time since the step began (ms)'
set ylabel 'relative |grad F|'
set logscale y
set format y '10^{%L}'
set key top right
plot for [mt in methods] fn using (strcol('model') eq mt && column('rep') == 0 ? column('wall_ms') : NaN):(column('rel_grad') > 0 ? column('rel_grad') : 1e-17) \
     with linespoints lw 2 pt 7 ps 0.6 lc rgb pcolor(methods, mt) title mt
unset logscale y
set format y '%g'

# ---- S1: shape matching against springs under explicit integration -----------------
set output out.'/locking_s1.'.ext
sscenes = distinct(fs, 'scene', '1')
series = distinct_n(fs, 'v("method") == "shape_matching" ? "alpha=" v("alpha") : v("method")', '1', 1)
skey(mt, a) = mt eq 'shape_matching' ? 'alpha='.a : mt
set multiplot layout 1, words(sscenes) title "S1: growth exponent of the shape error over each cell's second half (every cell the same simulated time)\n~2: falling (squares); above 4 (dashed): exponential; crosses (at 4.5 if not finite): unstable or diverged"
set yrange [-0.5:5]
set logscale x
set format x '10^{%L}'
set xlabel 'dt (s)'
set ylabel 'log_2 (envelope over (T/2, T] / over (T/4, T/2])'
set key top left font ',8'
do for [sc in sscenes] {
  set title sc
  plot for [s in series] fs using (strcol('scene') eq sc && skey(strcol('method'), strcol('alpha')) eq s ? column('dt_s') : NaN):'shape_growth_exponent' \
       with linespoints lw 2 pt 7 ps 0.7 lc rgb pcolor(series, s) title s, \
       fs using (strcol('scene') eq sc && strcol('class') ne 'stable' && strcol('class') ne 'falling' ? column('dt_s') : NaN):(strcol('shape_growth_exponent') eq 'nan' || strcol('shape_growth_exponent') eq '' ? 4.5 : column('shape_growth_exponent')) \
       with points pt 2 ps 2.5 lw 2 lc rgb '#d62728' title 'unstable or diverged', \
       fs using (strcol('scene') eq sc && strcol('class') eq 'falling' ? column('dt_s') : NaN):'shape_growth_exponent' \
       with points pt 4 ps 2 lw 2 lc rgb '#333333' title 'falling', \
       4 with lines lc rgb '#7f7f7f' dt 2 notitle
}
unset multiplot
set yrange [*:*]
