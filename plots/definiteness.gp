# definiteness (claims H1, H2): figures from results/definiteness*.csv and the
# final meshes results/definiteness_<scene>_<policy>.obj.
if (!exists("plots")) plots = 'plots'
load plots.'/common.gp'
f = results.'/definiteness.csv'
fp = results.'/definiteness_pair.csv'
# Scenes and policies come from the CSV (distinct() in common.gp); 'none' is
# named only as the exact Hessian, the subject of H1.
pols = distinct(f, 'policy', '1')
scenes = distinct(f, 'scene', '1')
npol = words(pols)
nsc = words(scenes)
PPAL = '#000000 #1f77b4 #2ca02c #d62728 #9467bd #17becf #e377c2 #bcbd22 #7f7f7f'
pc(p) = word(PPAL, (wordpos(pols, p) - 1) % words(PPAL) + 1)

# ---- residual against Newton iteration, per policy (H2) ----------------------
set output out.'/definiteness_residual.'.ext
res_cols = nsc > 1 ? int(ceil(sqrt(nsc))) : 1
set multiplot layout int(ceil(nsc / (res_cols * 1.0))), res_cols title "H2: Newton convergence per definiteness policy (|grad F| / |grad F(x^{(0)})|; none stops where CHOLMOD fails)"
# per scene the step shown: step 10, or the last step that every policy reached if earlier
array st[nsc]
do for [s = 1:nsc] {
  st[s] = 10
  do for [q in pols] {
    stats f using (strcol('scene') eq word(scenes, s) && strcol('policy') eq q ? column('step') : NaN) nooutput
    if (STATS_records > 0 && STATS_max < st[s]) { st[s] = int(STATS_max) }
  }
}
set logscale y
set format y '10^{%L}'
set xlabel 'Newton iteration'
set ylabel 'relative gradient norm'
# key where each panel has no data (the opaque box would hide curves)
# (by panel: the first panels' data leave these corners free)
kp(s) = s == 1 ? 'top right' : s == 2 ? 'bottom center' : 'bottom right'
do for [s = 1:nsc] {
  sc = word(scenes, s)
  eval 'set key '.kp(s)." font ',9'"
  set title sprintf('%s, step %d', sc, st[s])
  plot for [p = npol:1:-1] f using (strcol('scene') eq sc && strcol('policy') eq word(pols, p) && column('step') == st[s] ? column('newton_iter') : NaN):(column('rel_grad') > 0 ? column('rel_grad') : 1e-17) \
       with linespoints lw 2 pt (p == 1 ? 6 : 7) ps (p == 1 ? 1.8 : 0.6) lc rgb pc(word(pols, p)) title word(pols, p)
}
unset multiplot
unset logscale y
set format y '%g'

# ---- H1: smallest eigenvalue of A (spring pair; every Newton system) ---------
# One table per series: a NaN filter inside `using` would break every line,
# since the CSV interleaves dimensions and policies row by row.
# The series, from the pair CSV: none in the lowest dimension, then every
# policy in the highest, a policy with a buckling stiffness k_b at its
# smallest and largest k_b (- in skb: no k_b).
dims = distinct(fp, 'dim', '1')
dlo = word(dims, 1) + 0
dhi = word(dims, words(dims)) + 0
sdl = sprintf('%d ', dlo)
spl = 'none '
skl = '- '
do for [q in distinct(fp, 'policy', '1')] {
  kbs = distinct(fp, 'buckling_kb_n_m2', sprintf('v("policy") == "%s" && v("buckling_kb_n_m2") != ""', q))
  if (words(kbs) == 0) { sdl = sdl.sprintf('%d ', dhi); spl = spl.q.' '; skl = skl.'- ' } \
  else {
    kmin = word(kbs, 1); kmax = word(kbs, 1)
    do for [kb in kbs] { if (kb + 0 < kmin + 0) { kmin = kb }; if (kb + 0 > kmax + 0) { kmax = kb } }
    sdl = sdl.sprintf('%d %d ', dhi, dhi); spl = spl.q.' '.q.' '; skl = skl.kmin.' '.kmax.' '
  }
}
nser = words(spl)
sn(s) = sprintf('%dD, %s', word(sdl, s) + 0, word(spl, s)).(word(skl, s) eq '-' ? '' : ' k_b '.word(skl, s))
# colour: the policy's, a policy's later series the next of ALT; point type by series
ALT = '#ff7f0e #8c564b #e377c2 #17becf #bcbd22 #7f7f7f'
array spc[nser]
array spt[nser]
nalt = 0
do for [s = 1:nser] {
  first = 1
  do for [u = 1:s - 1] { if (word(spl, u) eq word(spl, s)) { first = 0 } }
  if (first) { spc[s] = pc(word(spl, s)) } else { nalt = nalt + 1; spc[s] = word(ALT, (nalt - 1) % words(ALT) + 1) }
  spt[s] = word('7 7 5 9 11 13 15 4 6 8 10 12', (s - 1) % 12 + 1) + 0
}
do for [s = 1:nser] {
  kbs_s = word(skl, s) eq '-' ? '' : word(skl, s)
  eval sprintf('set table $pair%d separator comma', s)
  plot fp using 'ratio':'min_eig_a_n_per_m' with table if (column('dim') == word(sdl, s) + 0 && strcol('policy') eq word(spl, s) && strcol('buckling_kb_n_m2') eq kbs_s)
  unset table
}
# the prediction lambda_min(A) = m/dt^2 + 2k(1 - L/l) (L = 1 m here), with
# m/dt^2 and 2k read from the CSV: A at l = L, and 1D A minus that
stats fp using (column('dim') == 3 && strcol('policy') eq 'none' && column('ratio') == 1 ? column('predicted_min_eig_a_n_per_m') : NaN) nooutput
m_dt2 = STATS_max
stats fp using (column('dim') == 1 && strcol('policy') eq 'none' ? column('predicted_min_eig_a_n_per_m') : NaN) nooutput
two_k = STATS_max - m_dt2
ratio_crit = two_k / (two_k + m_dt2)
stats fp using (column('dim') == 3 && strcol('policy') eq 'none' ? column('ratio') : NaN):(column('dim') == 3 && strcol('policy') eq 'none' ? column('min_eig_a_n_per_m') : NaN) nooutput
off_ratio = STATS_min_x
off_eig = STATS_min_y
set output out.'/definiteness_h1.'.ext
set multiplot layout 1,2 title "H1: A = M/dt^2 + H is indefinite only when springs are compressed, and only in 2D/3D"
set title 'spring pair held still (k = 8000 N/m, m = 1 kg, dt = 1/30 s)'
set arrow 1 from ratio_crit, graph 0 to ratio_crit, graph 1 nohead dt 3 lc rgb '#444444'
set label 2 sprintf('threshold %.3f', ratio_crit) at ratio_crit, graph 0.91 right offset -0.3, 0 font ',9'
set label 3 'predicted: m/dt^2 + 2k(1 - L/l)' at 0.46, -22000 font ',9' tc rgb '#444444'
set label 1 sprintf("none, 2D/3D at l/L = %g:\n%.0f N/m (off scale)", off_ratio, off_eig) at graph 0.03, graph 0.80 font ',9'
set xlabel 'compression l / L'
set ylabel 'smallest eigenvalue of A (N/m)'
set xrange [0.05:1.07]
set yrange [-40000:20000]
set samples 400
set key bottom right font ',8' noautotitle
plot for [s = 1:nser] sprintf('$pair%d', s) using 1:2 with linespoints lw 2 pt spt[s] lc rgb spc[s] title sn(s), \
     m_dt2 + two_k * (1 - 1 / x) with lines dt 2 lw 2 lc rgb '#444444' title 'predicted', \
     0 with lines lc rgb '#888888' notitle
set key autotitle columnheader
unset arrow 1
unset label 2
unset label 3
unset label 1
set title 'exact A at every Newton iterate (all runs)'
set xlabel 'fraction of compressed springs'
set ylabel 'smallest eigenvalue of exact A (N/m; Lanczos or dense)'
set xrange [-0.02:1.02]
set autoscale y
set key bottom left font ',9'
SPAL = '#1f77b4 #d62728 #2ca02c #9467bd #ff7f0e #8c564b #e377c2 #17becf'
plot for [s = 1:nsc] f using (strcol('scene') eq word(scenes, s) && column('system') == 1 ? column('compressed_frac') : NaN):'min_eig_exact_n_per_m' \
       with points pt 7 ps 0.5 lc rgb word(SPAL, (s - 1) % words(SPAL) + 1) title word(scenes, s), \
     0 with lines lc rgb '#888888' notitle
unset multiplot

# ---- final shapes side by side: the cloth scenes where the exact Hessian failed --------
# (from the runs CSV: none's run did not finish ok; a cloth: its OBJ has triangles)
fr = results.'/definiteness_runs.csv'
shape_rows = ''
do for [sc in distinct(fr, 'scene', 'v("policy") == "none" && v("status") != "ok"')] {
  if (system("grep -c '^f ' '".results.'/definiteness_'.sc."_none.obj' 2>/dev/null") + 0 > 0) { shape_rows = shape_rows.sc.' ' }
}
nrow = words(shape_rows)
if (ext eq 'svg') {
  set terminal svg size 1600,350 * (nrow > 0 ? nrow : 1) dynamic enhanced font 'sans,11' background rgb 'white'
} else {
  set terminal pngcairo size 1600,350 * (nrow > 0 ? nrow : 1) enhanced font 'sans,10'
}
set output out.'/definiteness_shapes.'.ext
if (nrow == 0) {
  # no cloth scene whose exact Hessian failed (a --smoke run has only the spring pair): say so, draw no shapes
  unset border; unset tics; unset key; unset title; unset xlabel; unset ylabel
  set label 1 'H2: no cloth scene in this run has a none policy run that failed, so there are no final shapes to compare' at graph 0.5, 0.5 center
  plot [0:1][0:1] NaN notitle
  unset label 1
}
if (nrow > 0) {
# simulated time of each row, from the steps CSV (the quick run has fewer steps)
fs = results.'/definiteness_steps.csv'
times = ''
do for [sc in shape_rows] {
  stats fs using (strcol('scene') eq sc ? column('t_s') : NaN) nooutput
  times = times.(times eq '' ? '' : ' and ').sprintf('%.2g s (%s)', STATS_max, sc)
}
set datafile separator whitespace
set multiplot layout nrow,npol title sprintf("H2: final shapes per policy after %s; none shows its state when CHOLMOD failed at step 1", times)
set autoscale
set zrange [-5:1]
set cbrange [-5:1]
set view equal xyz
unset key
set view 60, 30
set xlabel 'x (m)'
set ylabel 'z (m)'
set zlabel 'y (m)' rotate
set xyplane 0
set palette defined (0 '#08306b', 1 '#4292c6', 2 '#c6dbef')
unset colorbox
do for [row in shape_rows] {
  do for [q in pols] {
    set title sprintf('%s: %s', row, q)
    g = results.'/definiteness_'.row.'_'.q.'.obj'
    splot g using (strcol(1) eq 'v' ? $2 : NaN):4:3:3 with points pt 7 ps 0.4 palette
  }
}
unset multiplot
}
