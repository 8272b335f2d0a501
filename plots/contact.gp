# contact (claim C1): the worst exact intersection count over a cell's frames against dt, per response
# and drop speed, one panel per scene. Data: results/contact.csv (one row per frame; a cell is scene,
# response, dt_s, speed_m_per_s). Responses, scenes and speeds come from the CSV.
load 'plots/common.gp'

main = results.'/contact.csv'
SC = distinct(main, 'scene', 'v("frame") != ""')
R = distinct(main, 'response', 'v("frame") != ""')
SP = distinct(main, 'speed_m_per_s', 'v("frame") != ""')
# per cell of scene s, response r, speed sp: dt and the worst intersection count over its frames (one line
# per cell, in dt order)
cells(s, r, sp) = "< awk -F, '".AWK_HEAD."v(\"intersections\") != \"\" && v(\"scene\") == \"".s."\" && v(\"response\") == \"".r."\" && v(\"speed_m_per_s\") == \"".sp."\" { k = v(\"scene\") \" \" v(\"response\") \" \" v(\"dt_s\") \" \" v(\"speed_m_per_s\"); if (!(k in w)) { o[++m] = k; w[k] = 0 } n = v(\"intersections\") + 0; if (n > w[k]) w[k] = n; f[k]++ } END { for (j = 1; j <= m; j++) print o[j], w[o[j]], f[o[j]] }' '".main."' | sort -g -k3"

set output out.'/contact.'.ext
if (ext eq 'svg') { set terminal svg size 1300,600 dynamic enhanced font 'sans,12' background rgb 'white' } \
else { set terminal pngcairo size 1300,600 enhanced font 'sans,11' }
set datafile separator whitespace
set key noautotitle  # the per-cell lines have no header row
set multiplot layout 1, words(SC) title 'C1: worst intersecting triangle pairs in a frame (cloth-cloth + cloth-obstacle, exact) against dt'
set logscale x
set xlabel 'dt (s)'
set ylabel 'worst intersecting pairs over the frames of a cell'
set yrange [-1:*]
set key below horizontal maxrows 2
do for [s in SC] {
  set title s noenhanced
  plot for [r in R] for [sp in SP] cells(s, r, sp) using 3:5 \
       with linespoints lc rgb pcolor(R, r) pt (wordpos(SP, sp) + 4) ps 1.0 title r.', drop '.sp.' m/s'
}
unset multiplot

# C2: ipc's friction on the slope (results/contact_c2.csv): the slide after the run's time against mu / tan theta,
# one line per angle, the sliding block's closed form dashed, and each angle's measured threshold mu* / tan theta
# as a vertical mark (Coulomb's law puts it at 1).
c2 = results.'/contact_c2.csv'
if (system("test -f '".c2."' && echo y") eq "y") {
  TH = distinct(c2, 'theta_deg', 'v("kind") == "slide" && v("integrator") != "vbd" && v("slide_m") != ""')
  slides(th) = "< awk -F, '".AWK_HEAD."v(\"kind\") == \"slide\" && v(\"integrator\") != \"vbd\" && v(\"slide_m\") != \"\" && v(\"theta_deg\") == \"".th."\" { print v(\"mu_over_tan\"), v(\"slide_m\"), v(\"closed_form_m\") }' '".c2."' | sort -g"
  thr(th) = "< awk -F, '".AWK_HEAD."v(\"kind\") == \"threshold\" && v(\"mu_over_tan\") != \"\" && v(\"theta_deg\") == \"".th."\" { print v(\"mu_over_tan\"), 1e-6; print v(\"mu_over_tan\"), 1 }' '".c2."'"
  set output out.'/contact_c2.'.ext
  if (ext eq 'svg') { set terminal svg size 900,600 dynamic enhanced font 'sans,12' background rgb 'white' } \
  else { set terminal pngcairo size 900,600 enhanced font 'sans,11' }
  set datafile separator whitespace
  unset logscale
  set logscale y
  set xrange [0:*]
  set yrange [1e-6:1]
  set xlabel 'mu / tan theta'
  set ylabel 'slide along the slope (m)'
  set title 'C2: ipc friction on the slope: slide against mu, sliding block dashed, measured threshold mu* vertical'
  set key top right
  plot for [th in TH] slides(th) using 1:2 with linespoints lc rgb pcolor(TH, th) pt 7 title 'theta = '.th.' deg', \
       for [th in TH] slides(th) using 1:($3 > 0 ? $3 : NaN) with lines dt 2 lc rgb pcolor(TH, th) notitle, \
       for [th in TH] thr(th) using 1:2 with lines lw 2 lc rgb pcolor(TH, th) notitle
}

# C3: error against time (results/contact_c3.csv): one step from the same contact-rich state, each method's ladder
# of iteration caps as a line (log-log), step_error against IPC's converged step against the step's wall time
# (median of the interleaved repeats, the bar from the fastest to the slowest repeat), colour per method, point
# type per scene; the targets 1e-2 and 1e-3 dashed; a row whose result intersects circled.
c3 = results.'/contact_c3.csv'
if (system("test -f '".c3."' && echo y") eq "y") {
  SC3 = distinct(c3, 'scene', 'v("method") != "reference" && v("step_error") != ""')
  M3 = distinct(c3, 'method', 'v("method") != "reference" && v("step_error") != ""')
  ladder(s, m) = "< awk -F, '".AWK_HEAD."v(\"scene\") == \"".s."\" && v(\"method\") == \"".m."\" && v(\"step_error\") + 0 > 0 && v(\"wall_ms\") != \"\" && (v(\"status\") == \"ok\" || v(\"status\") == \"max_iters\") { lo = v(\"wall_min_ms\"); hi = v(\"wall_max_ms\"); if (lo == \"\") lo = v(\"wall_ms\"); if (hi == \"\") hi = v(\"wall_ms\"); print v(\"wall_ms\"), v(\"step_error\"), lo, hi, v(\"intersections\") + 0 }' '".c3."' | sort -g"
  set output out.'/contact_c3.'.ext
  if (ext eq 'svg') { set terminal svg size 1000,720 dynamic enhanced font 'sans,12' background rgb 'white' } \
  else { set terminal pngcairo size 1000,720 enhanced font 'sans,11' }
  set datafile separator whitespace
  unset logscale
  unset xrange
  unset yrange
  set logscale xy
  set xrange [*:*]
  set yrange [*:*]
  set format y '10^{%T}'
  set xlabel 'wall time of the step (ms; median of the repeats, bar: fastest to slowest)'
  set ylabel 'step error |x - x*| / |x* - x_{start}|'
  set title 'C3: error against time for one step from a contact-rich state (x* = IPC Newton, converged)'
  set key below horizontal maxrows 3 width 2
  plot 1e-2 with lines dt 2 lc rgb 'gray40' title 'target 1e-2', \
       1e-3 with lines dt 3 lc rgb 'gray40' title 'target 1e-3', \
       for [s in SC3] for [m in M3] ladder(s, m) using 1:2:3:4 with xerrorbars lc rgb pcolor(M3, m) pt (wordpos(SC3, s) + 4) ps 0.9 notitle, \
       for [s in SC3] for [m in M3] ladder(s, m) using 1:2 with lines lc rgb pcolor(M3, m) dt wordpos(SC3, s) title m.', '.s noenhanced, \
       for [s in SC3] for [m in M3] ladder(s, m) using 1:($5 > 0 ? $2 : NaN) with points pt 6 ps 2.5 lw 2 lc rgb 'red' notitle
}
