# bending (claims B1, B2, B3): restoring force against fold angle, the two
# drape rest shapes side by side, quadratic against hinge energy under stretch.
# Data: results/bending.csv and results/bending_rest_<model>.dat.
load 'plots/common.gp'

main = results.'/bending.csv'

# ---- B1: restoring force at the wing tip against the fold angle -------------
set output out.'/bending_b1_force.'.ext
M1 = distinct(main, 'model', 'v("part") == "b1"')
set logscale xy
set xlabel 'fold angle (deg)'
set ylabel 'restoring force at the wing tip (N, bend\_k = 1)'
set title 'B1: bending force near the flat state (slopes: spring 3, hinges 1)'
set key left top
plot for [m in M1] main using (strcol('part') eq 'b1' && strcol('model') eq m ? column('angle_deg') : NaN):(column('force_n')) \
     with linespoints lc rgb pcolor(M1, m) pt 7 ps 0.6 title m
unset logscale

# ---- B3: quadratic over hinge energy on the strip against the peak stretch -
set output out.'/bending_b3_stretch.'.ext
M3 = distinct(main, 'mesh', 'v("part") == "b3"')
set xlabel 'peak in-plane stretch of the ramp (%)'
set ylabel 'E_{quadratic} / E_{hinge}'
set title 'B3: a curved, jittered strip under a non-uniform stretch (along the arc or the axis); band: within 10%'
set key left top
set yrange [*:*]
plot 0.9 with lines dt 2 lc rgb '#7f7f7f' notitle, 1.1 with lines dt 2 lc rgb '#7f7f7f' notitle, \
     for [m in M3] main using (strcol('part') eq 'b3' && strcol('mesh') eq m ? 100 * column('stretch') : NaN):(column('ratio')) \
     with linespoints lc rgb pcolor(M3, m) pt 7 ps 0.6 title m

# ---- B2: the drape's rest shapes side by side, coloured by height -----------
if (ext eq 'svg') { set terminal svg size 1400,650 dynamic enhanced font 'sans,12' background rgb 'white' } \
else { set terminal pngcairo size 1400,650 enhanced font 'sans,11' }
set output out.'/bending_b2_rest.'.ext
M2 = distinct(main, 'model', 'v("part") == "b2" && v("mesh") == "grid"')
set datafile separator whitespace
set multiplot layout 1, words(M2) title 'B2: the drape at rest (finest grid), coloured by height'
set view 62, 30, 1, 1
set view equal xyz
set xyplane at -0.6
unset key
set xlabel 'x (m)'
set ylabel 'z (m)'
set zlabel 'height y (m)'
set pm3d depthorder border lw 0.3 lc rgb '#404040'
set palette rgbformulae 33,13,10
set cbrange [-0.55:0.0]
unset grid
do for [m in M2] {
  set title m
  splot results.'/bending_rest_'.m.'.dat' using 1:3:2 with pm3d notitle
}
unset multiplot
