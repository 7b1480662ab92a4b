# A line chart of a CSV file: the first row names the columns, the first
# column is x, every other column is one line (titled by its header).
# Writes outbase.png and outbase.svg.
# Variables (gnuplot -e "name=value; ..."):
#   datafile, outbase     required: input CSV and output path without extension
#   title, xlabel, ylabel optional strings
#   logx, logy            optional, 1 for a logarithmic axis
#   points                optional, 0 for lines without point marks
if (!exists("datafile") || !exists("outbase")) {
  print "chart_lines.gp: set datafile and outbase with -e"
  exit status 2
}
if (!exists("title")) title = ""
if (!exists("xlabel")) xlabel = ""
if (!exists("ylabel")) ylabel = ""
if (!exists("logx")) logx = 0
if (!exists("logy")) logy = 0
if (!exists("points")) points = 1

set datafile separator comma
set key autotitle columnheader
set key top left noenhanced
set title title noenhanced
set xlabel xlabel noenhanced
set ylabel ylabel noenhanced
set grid
if (logx) { set logscale x }
if (logy) { set logscale y }
style = points ? "linespoints" : "lines"

# pngcairo draws smoother lines; gnuplot-nox builds may only have png (libgd).
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 900,600 noenhanced
} else {
  set terminal png size 900,600 noenhanced
}
set output outbase.".png"
plot for [i=2:*] datafile using 1:i with @style linewidth 2
set terminal svg size 900,600 dynamic noenhanced
set output outbase.".svg"
replot
unset output
