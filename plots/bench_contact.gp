# Figure of make bench's contact rows (results/bench_contact_steps.csv, bench/bench_contact.c): the time of each ipc
# step on the rotating sphere split into its phases (broad phase, CCD, barrier, linear solve, the rest) against the
# step's contact count (pairs within d-hat at its end), the warm-up steps (the sheet landing) and the first round's
# timed steps, per size; left per step, right per Newton iteration. Sizes and phases come from the CSV's columns and
# rows, never typed as data here; a step without contacts (before the landing) has no point on the log axes.
load 'plots/common.gp'
steps = results.'/bench_contact_steps.csv'
sizes = distinct(steps, 'n', 'v("method") == "ipc"')
phases = 'broad_ms ccd_ms barrier_ms solve_ms rest_ms'
# the header and the ipc rows of size n with contacts
rows(n) = "< awk -F, '/^#/ { next } !h { h = 1; for (i = 1; i <= NF; i++) ix[$i] = i; print; next } $ix[\"method\"] == \"ipc\" && $ix[\"n\"] == \"".n."\" && $ix[\"contacts\"] > 0' '".steps."'"
pname(p) = p[1:strlen(p) - 3]

set output out.'/bench_contact.'.ext
set terminal push
if (ext eq 'svg') { set terminal svg size 1400,600 dynamic enhanced font 'sans,11' background rgb 'white' } \
else { set terminal pngcairo size 1400,600 enhanced font 'sans,10' }
set multiplot layout 1, 2 title 'IPC on the rotating sphere: time split against the contact count (make bench; one point per step)'
set logscale xy
set xlabel 'contacts (pairs within d-hat at the end of the step)'
set key top left
set title 'per step'
set ylabel 'ms per step'
plot for [n in sizes] for [p in phases] rows(n) using 'contacts':p with points pt (5 + 2 * (wordpos(sizes, n) - 1)) ps 1.2 lc rgb pcolor(phases, p) title pname(p).' '.n.'^2' noenhanced
set title 'per Newton iteration'
set ylabel 'ms per Newton iteration'
plot for [n in sizes] for [p in phases] rows(n) using 'contacts':(column(p) / column('newton_iters')) with points pt (5 + 2 * (wordpos(sizes, n) - 1)) ps 1.2 lc rgb pcolor(phases, p) title pname(p).' '.n.'^2' noenhanced
unset multiplot
set terminal pop
