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
set key top right font ',9'
do for [s = 1:4] {
  set title sprintf('%s, step %d', sc[s], st[s])
  plot for [p = 5:1:-1] f using (strcol('scene') eq sc[s] && strcol('policy') eq pol[p] && column('step') == st[s] ? column('newton_iter') : NaN):(column('rel_grad') > 0 ? column('rel_grad') : 1e-17) \
       with linespoints lw 2 pt (p == 1 ? 6 : 7) ps (p == 1 ? 1.8 : 0.6) lc rgb pc[p] title pol[p]
}
unset multiplot
unset logscale y
set format y '%g'

# ---- H1: smallest eigenvalue of A (spring pair; every Newton system) ---------
set output out.'/definiteness_h1.'.ext
set multiplot layout 1,2 title "H1: A = M/dt^2 + H is indefinite only when springs are compressed, and only in 2D/3D"
set title 'spring pair held still (k = 8000 N/m, m = 1 kg, dt = 1/30 s)'
set label 1 'none, 2D/3D at l/L = 0.1: -143100 (off scale)' at graph 0.03, graph 0.32 font ',9'
set xlabel 'compression l / L'
set ylabel 'smallest eigenvalue of A (N/m)'
set xrange [0.05:1.07]
set yrange [-40000:20000]
set key bottom right font ',9'
plot fp using (column('dim') == 1 && strcol('policy') eq 'none' ? column('ratio') : NaN):'min_eig_a' with linespoints lw 2 pt 7 lc rgb '#000000' title '1D, none (E" = k)', \
     fp using (column('dim') == 3 && strcol('policy') eq 'none' ? column('ratio') : NaN):'min_eig_a' with linespoints lw 2 pt 7 lc rgb '#ff7f0e' title '2D/3D, none', \
     fp using (column('dim') == 3 && strcol('policy') eq 'none' ? column('ratio') : NaN):'predicted_min_eig_a' with lines dt 2 lw 2 lc rgb '#444444' title 'predicted m/dt^2 + 2k(1 - L/l)', \
     fp using (column('dim') == 3 && strcol('policy') eq 'drop' ? column('ratio') : NaN):'min_eig_a' with linespoints lw 2 pt 5 lc rgb pc[2] title '3D, drop', \
     fp using (column('dim') == 3 && strcol('policy') eq 'mirror' ? column('ratio') : NaN):'min_eig_a' with linespoints lw 2 pt 9 lc rgb pc[3] title '3D, mirror', \
     fp using (column('dim') == 3 && strcol('policy') eq 'choi-ko' && column('buckling_kb') == 0.01 ? column('ratio') : NaN):'min_eig_a' with linespoints lw 2 pt 11 lc rgb pc[5] title '3D, choi-ko k_b = 0.01', \
     fp using (column('dim') == 3 && strcol('policy') eq 'choi-ko' && column('buckling_kb') == 10 ? column('ratio') : NaN):'min_eig_a' with linespoints lw 2 pt 13 lc rgb '#8c564b' title '3D, choi-ko k_b = 10', \
     0 with lines lc rgb '#888888' notitle
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
set datafile separator whitespace
set multiplot layout 2,5 title "Final shapes per policy after 1 s (driven) and 0.67 s (scaled); none shows its state when CHOLMOD failed at step 1"
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
