# A stability map from a CSV file with the columns
#   dt, stiffness, status, cells, t, reason
# (status 0 stable, 1 NaN or inf, 2 energy growth, 3 inverted elements,
# 4 velocity beyond bound, 5 step failed): one coloured square per cell,
# dt on a log x axis, the stiffness on a log (logy=1) or linear y axis,
# only the rows whose `cells` column equals the variable cells (when set).
# With bound=1 the explicit bound of one spring under symplectic Euler,
# dt = 2 sqrt(m / k), i.e. k = 4 m / dt^2, is drawn as a curve.
# Writes outbase.png and outbase.svg.
# Variables (gnuplot -e "name=value; ..."):
#   datafile, outbase   required
#   title, ylabel       optional strings
#   logy                optional, 1 (default) for a logarithmic stiffness axis
#   cells               optional, only rows with this mesh size (default: all)
#   bound, mass         optional, bound=1 draws dt = 2 sqrt(mass / k) (mass default 1)
#   psize               optional, the squares' point size (default 3)
#   boundfile           optional CSV: cells, stiffness, largest stable dt, ..., column 6 a
#                       lower estimate of it; both drawn against the stiffness
#   xlabel, logx        optional: another x axis than dt (logx 0: linear)
#   group               optional, only rows whose column 4 is this string (instead of cells)
#   region_x, region_y  optional: a dashed box from the axes' low corner to (region_x,
#                       region_y), titled regiontitle
#   curve, curvetitle   optional: a gnuplot expression in x drawn as a line (a prediction)
if (!exists("datafile") || !exists("outbase")) {
  print "chart_map.gp: set datafile and outbase with -e"
  exit status 2
}
if (!exists("title")) title = ""
if (!exists("ylabel")) ylabel = "stiffness"
if (!exists("logy")) logy = 1
if (!exists("cells")) cells = -1
if (!exists("bound")) bound = 0
if (!exists("mass")) mass = 1.0
if (!exists("psize")) psize = 3
if (!exists("xlabel")) xlabel = "time step dt (s)"
if (!exists("logx")) logx = 1
if (!exists("regiontitle")) regiontitle = "region"
if (!exists("curvetitle")) curvetitle = "prediction"
sel = exists("group") ? "(strcol(4) eq group)" : "(cells < 0 || $4 == cells)"

array names[6] = ["stable", "NaN or inf", "energy growth", "inverted elements", \
                  "velocity beyond bound", "step failed"]
# the palette beside this script; each status and line its own colour of it
tb_dir = ""
do for [k = strlen(ARG0):1:-1] { if (tb_dir eq "" && ARG0[k:k] eq "/") { tb_dir = ARG0[1:k] } }
load tb_dir."palette.gp"
array colours[6] = [tb_colours[3], tb_colours[13], tb_colours[2], tb_colours[5], \
                    tb_colours[4], tb_colours[12]]
c_bound = tb_colours[14]; c_bisected = tb_colours[1]; c_linearised = tb_colours[10]

set datafile separator comma
set key outside right top noenhanced box opaque
set title title noenhanced
set xlabel xlabel noenhanced
set ylabel ylabel noenhanced
if (logx) { set logscale x; set format x "%g" }
if (logy) { set logscale y; set format y "%g" }
set grid
# the axes span the cells (the bound's curve is clipped to them)
stats datafile skip 1 using 1 nooutput
if (logx) { xlo = STATS_min / 1.6; xhi = STATS_max * 1.6 } else {
  pad = (STATS_max - STATS_min) * 0.08 + 1e-3; xlo = STATS_min - pad; xhi = STATS_max + pad
}
stats datafile skip 1 using 2 nooutput
if (logy) { ylo = STATS_min / 1.6; yhi = STATS_max * 1.6 } else {
  pad = (STATS_max - STATS_min) * 0.08 + 1e-3; ylo = STATS_min - pad; yhi = STATS_max + pad
}
set xrange [xlo:xhi]
set yrange [ylo:yhi]

if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
  set terminal pngcairo size 1000,650 noenhanced
} else {
  set terminal png size 1000,650 noenhanced
}
set output outbase.".png"
# measured bounds: rows cells, stiffness, largest stable dt, ..., a lower estimate (column 6)
extra = ""
if (exists("boundfile")) {
  extra = ", boundfile skip 1 using (($1 == cells || cells < 0) ? $3 : 1/0):2 " . \
          "with linespoints linewidth 2 pointtype 7 pointsize 1.2 linecolor rgb '" . c_bisected . "' " . \
          "title 'largest stable dt (bisected)', " . \
          "boundfile skip 1 using (($1 == cells || cells < 0) ? $6 : 1/0):2 " . \
          "with lines linewidth 2 dashtype 2 linecolor rgb '" . c_linearised . "' " . \
          "title 'mesh, linearised, with damping'"
}
if (exists("region_x") && exists("region_y")) {
  set object 1 rectangle from graph 0, graph 0 to first region_x, first region_y \
    fillstyle empty border linecolor rgb c_bound linewidth 2 dashtype 2 front
  extra = extra . ", 1/0 with lines linewidth 2 dashtype 2 linecolor rgb c_bound title regiontitle"
}
if (exists("curve")) {
  set samples 1000
  extra = extra . ", " . curve . " with lines linewidth 2 linecolor rgb c_bisected title curvetitle"
}
# one series per status; the bound's curve only where asked for
plot for [i = 0:5] datafile skip 1 \
       using 1:((@sel && $3 == i) ? $2 : 1/0) \
       with points pointtype 5 pointsize psize linecolor rgb colours[i + 1] title names[i + 1], \
     (bound ? 4 * mass / x**2 : 1/0) with lines linewidth 2 linecolor rgb c_bound \
       title (bound ? "dt = 2 sqrt(m/k), one spring" : "") @extra
set terminal svg size 1000,650 dynamic noenhanced
set output outbase.".svg"
replot
unset output
