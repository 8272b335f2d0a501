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
