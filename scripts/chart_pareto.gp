# Speed against accuracy (figure pareto): a log-log scatter of the rms
# error against the reference (y) against steps per second (x), one colour
# per model, the Pareto front as a line. The data file (CSV) holds one
# block per model and a last block for the front, blocks separated by two
# blank lines, each starting with a header line "name,rms error".
# Variables (gnuplot -e "name=value; ..."):
#   datafile, outbase  required: input CSV, output path without extension
#   nmodels            required: the number of model blocks (the front follows)
#   title              optional
if (!exists("datafile") || !exists("outbase") || !exists("nmodels")) {
  print "chart_pareto.gp: set datafile, outbase and nmodels with -e"
  exit status 2
}
if (!exists("title")) title = ""

# the palette beside this script: model i in colour and marker i, the front in the last
tb_dir = ""
do for [k = strlen(ARG0):1:-1] { if (tb_dir eq "" && ARG0[k:k] eq "/") { tb_dir = ARG0[1:k] } }
load tb_dir."palette.gp"
if (nmodels >= tb_ncolours) {
  print "chart_pareto.gp: more models than colours in scripts/palette.gp"
  exit status 2
}

set datafile separator comma
set key outside right top noenhanced
set title title noenhanced
set xlabel "steps per second (1/s, log)"
set ylabel "rms surface error / largest reference displacement (dimensionless, log)"
set logscale x
set logscale y
set grid
set format y "%g"

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1000,600 noenhanced
} else {
  set terminal png size 1000,600 noenhanced
}
set output outbase.".png"
plot for [i=0:nmodels-1] datafile index i using 1:2 with points linetype (i + 1) pointsize 1.6 \
       title columnheader(1), \
     datafile index nmodels using 1:2 with linespoints linewidth 2 \
       linecolor rgb tb_colours[tb_ncolours] pointtype 6 pointsize 2.4 title "Pareto front"
set terminal svg size 1000,600 dynamic noenhanced
set output outbase.".svg"
replot
unset output
