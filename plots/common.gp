# Shared gnuplot settings, loaded by every plots/<experiment>.gp.
# scripts/plots.sh sets: ext ('png' or 'svg'), out (output folder), results
# (CSV folder) and plots (this folder), as absolute paths, so a script runs
# from any directory:
#   gnuplot -e "plots='/path/plots'; results='/path/results'; out='/tmp'" /path/plots/x.gp
# Each figure then does: set output out.'/<name>.'.ext
if (!exists("ext")) ext = 'png'
if (!exists("out")) out = 'plots/out'
if (!exists("results")) results = 'results'
if (ext eq 'svg') {
  set terminal svg size 900,600 dynamic enhanced font 'sans,12' background rgb 'white'
} else {
  set terminal pngcairo size 900,600 enhanced font 'sans,11'
}
set datafile separator ','
set datafile commentschars '#'
set key autotitle columnheader
set grid
set key box opaque

# Names come from the CSV, never from a list typed in a script:
# distinct(file, col, cond) is the distinct values of column `col` (by its
# header name) over the data rows of `file` where the awk condition `cond`
# holds, space-separated in order of first appearance (words(), word() and
# `for [s in ...]` walk it). In cond, v("name") is a row's value in the
# column of that name, e.g. 'v("sweep") == "main"'; '1' takes every row.
# distinct_n(file, expr, cond, nmin) keeps the values of the awk expression
# `expr` (e.g. 'v("scene") ":" v("k_n_per_m")') met on at least nmin such rows.
# (concatenated, not sprintf'ed: gnuplot's sprintf truncates long strings)
AWK_HEAD = "function v(n) { return $ix[n] } /^#/ { next } !h { for (i = 1; i <= NF; i++) ix[$i] = i; h = 1; next } "
distinct_n(file, expr, cond, nmin) = system("awk -F, '".AWK_HEAD."(".cond.") { key = ".expr."; if (!(key in c)) o[++m] = key; c[key]++ } END { for (j = 1; j <= m; j++) if (c[o[j]] >= ".sprintf("%d", nmin).") printf \"%s \", o[j] }' '".file."'")
distinct(file, col, cond) = distinct_n(file, 'v("'.col.'")', cond, 1)
# the parts of a 'a:b' pair
pair1(p) = p[1:strstrt(p, ':') - 1]
pair2(p) = p[strstrt(p, ':') + 1:]
# position (1, 2, ...) of word w in the list, 0 if absent
wordpos(list, w) = sum [k = 1:words(list)] (word(list, k) eq w ? k : 0)
# series colours by position in a list of names (the first five are the figures' historical ones)
PALETTE = "#000000 #9467bd #2ca02c #1f77b4 #ff7f0e #d62728 #8c564b #e377c2 #17becf #bcbd22 #7f7f7f"
pcolor(list, w) = word(PALETTE, (wordpos(list, w) - 1) % words(PALETTE) + 1)
