# Shared gnuplot settings, loaded by every plots/<experiment>.gp.
# scripts/plots.sh sets: ext ('png' or 'svg'), out (output folder), results
# (CSV folder). Each figure then does: set output out.'/<name>.'.ext
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
