# Figure of make bench SCALE=1 (results/bench_scale.csv, bench/bench_scale.c):
# time per step and peak RSS against the number of vertices, log-log, one
# series per method. The methods are read from the CSV, never typed here; a
# configuration that failed or was skipped has no point (its status row says why).
load 'plots/common.gp'
main = results.'/bench_scale.csv'
methods = distinct(main, 'method', '1')
# the header and the rows of method m that were measured (a step time)
rows(m) = "< awk -F, '/^#/ { next } !h { h = 1; for (i = 1; i <= NF; i++) ix[$i] = i; print; next } $1 == \"".m."\" && $ix[\"step_ms\"] != \"\"' '".main."'"

set output out.'/bench_scale.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1400,600 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1400,600 enhanced font 'sans,10' }
set multiplot layout 1, 2 title 'Scaling to a million vertices: one process per (method, size), one BLAS thread'
set logscale xy
set format x '10^{%T}'
set format y '10^{%T}'
set xlabel 'vertices N'
set key bottom right
set title 'time per step (median of the steps after a warm-up step)'
set ylabel 'ms per step'
plot for [m in methods] rows(m) using 'vertices':'step_ms' with linespoints pt 7 lw 2 lc rgb pcolor(methods, m) title m noenhanced, \
     [1000:2e6] 1e-3 * x with lines dt 2 lc 'gray' title 'slope 1 (reference)'
set title 'peak resident set of the process (ru\_maxrss)'
set ylabel 'MiB'
plot for [m in methods] rows(m) using 'vertices':(column('peak_rss_bytes') / 1048576) with linespoints pt 7 lw 2 lc rgb pcolor(methods, m) title m noenhanced, \
     [1000:2e6] 1e-2 * x with lines dt 2 lc 'gray' title 'slope 1 (reference)'
unset multiplot
set terminal pop
