# definiteness (claims H1, H2): figures from results/definiteness*.csv and the
# final meshes results/definiteness_<scene>_<policy>.obj.
load 'plots/common.gp'
f = results.'/definiteness.csv'
fp = results.'/definiteness_pair.csv'
array pol[5] = ['none', 'drop', 'mirror', 'shift', 'choi-ko']
array pc[5] = ['#000000', '#1f77b4', '#2ca02c', '#d62728', '#9467bd']

# ---- residual against Newton iteration, per policy (H2) ----------------------
set output out.'/definiteness_residual.'.ext
set multiplot layout 2,2 title "H2: Newton convergence per definiteness policy (|grad F| / |grad F(x^{(0)})|; none stops where CHOLMOD fails)"
array sc[4] = ['hanging', 'scaled', 'driven', 'pair']
array st[4] = [10, 1, 1, 1]
# the quick run has fewer hanging steps: show the last one if it is before step 10
stats f using (strcol('scene') eq 'hanging' ? column('step') : NaN) nooutput
if (STATS_max < 10) { st[1] = int(STATS_max) }
set logscale y
set format y '10^{%L}'
set xlabel 'Newton iteration'
set ylabel 'relative gradient norm'
# key where each panel has no data (the opaque box would hide curves)
array kp[4] = ['top right', 'bottom center', 'bottom right', 'bottom right']
do for [s = 1:4] {
  eval 'set key '.kp[s]." font ',9'"
  set title sprintf('%s, step %d', sc[s], st[s])
  plot for [p = 5:1:-1] f using (strcol('scene') eq sc[s] && strcol('policy') eq pol[p] && column('step') == st[s] ? column('newton_iter') : NaN):(column('rel_grad') > 0 ? column('rel_grad') : 1e-17) \
       with linespoints lw 2 pt (p == 1 ? 6 : 7) ps (p == 1 ? 1.8 : 0.6) lc rgb pc[p] title pol[p]
}
unset multiplot
unset logscale y
set format y '%g'

# ---- H1: smallest eigenvalue of A (spring pair; every Newton system) ---------
# One table per series: a NaN filter inside `using` would break every line,
# since the CSV interleaves dimensions and policies row by row.
array sd[6] = [1, 3, 3, 3, 3, 3]
array sp[6] = ['none', 'none', 'drop', 'mirror', 'choi-ko', 'choi-ko']
array skb[6] = ['', '', '', '', '0.01', '10']
array sn[6] = ['1D, none (E" = k)', '2D/3D, none', '3D, drop', '3D, mirror', '3D, choi-ko k_b 0.01', '3D, choi-ko k_b 10']
array spc[6] = ['#000000', '#ff7f0e', pc[2], pc[3], pc[5], '#8c564b']
array spt[6] = [7, 7, 5, 9, 11, 13]
do for [s = 1:6] {
  eval sprintf('set table $pair%d separator comma', s)
  plot fp using 'ratio':'min_eig_a' with table if (column('dim') == sd[s] && strcol('policy') eq sp[s] && strcol('buckling_kb') eq skb[s])
  unset table
}
# the prediction lambda_min(A) = m/dt^2 + 2k(1 - L/l) (L = 1 m here), with
# m/dt^2 and 2k read from the CSV: A at l = L, and 1D A minus that
stats fp using (column('dim') == 3 && strcol('policy') eq 'none' && column('ratio') == 1 ? column('predicted_min_eig_a') : NaN) nooutput
m_dt2 = STATS_max
stats fp using (column('dim') == 1 && strcol('policy') eq 'none' ? column('predicted_min_eig_a') : NaN) nooutput
two_k = STATS_max - m_dt2
ratio_crit = two_k / (two_k + m_dt2)
stats fp using (column('dim') == 3 && strcol('policy') eq 'none' ? column('ratio') : NaN):(column('dim') == 3 && strcol('policy') eq 'none' ? column('min_eig_a') : NaN) nooutput
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
plot for [s = 1:6] sprintf('$pair%d', s) using 1:2 with linespoints lw 2 pt spt[s] lc rgb spc[s] title sn[s], \
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
array scc[4] = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd']
plot for [s = 1:4] f using (strcol('scene') eq sc[s] && column('system') == 1 ? column('compressed_frac') : NaN):'min_eig_exact' \
       with points pt 7 ps 0.5 lc rgb scc[s] title sc[s], \
     0 with lines lc rgb '#888888' notitle
unset multiplot

# ---- final shapes side by side (driven: pins pushed together; scaled: 0.7x) ---
if (ext eq 'svg') {
  set terminal svg size 1600,700 dynamic enhanced font 'sans,11' background rgb 'white'
} else {
  set terminal pngcairo size 1600,700 enhanced font 'sans,10'
}
set output out.'/definiteness_shapes.'.ext
# simulated time of each row, from the steps CSV (the quick run has fewer steps)
fs = results.'/definiteness_steps.csv'
stats fs using (strcol('scene') eq 'driven' ? column('t_s') : NaN) nooutput
t_driven = STATS_max
stats fs using (strcol('scene') eq 'scaled' ? column('t_s') : NaN) nooutput
t_scaled = STATS_max
set datafile separator whitespace
set multiplot layout 2,5 title sprintf("H2: final shapes per policy after %.2g s (driven) and %.2g s (scaled); none shows its state when CHOLMOD failed at step 1", t_driven, t_scaled)
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
do for [row in 'driven scaled'] {
  do for [p = 1:5] {
    set title sprintf('%s: %s', row, pol[p])
    g = results.'/definiteness_'.row.'_'.pol[p].'.obj'
    splot g using (strcol(1) eq 'v' ? $2 : NaN):4:3:3 with points pt 7 ps 0.4 palette
  }
}
unset multiplot
