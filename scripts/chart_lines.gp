# A line chart of a CSV file: the first row names the columns, the first
# column is x, every other column is one series (titled by its header), in
# the colours and markers of scripts/palette.gp, the key outside the data area.
# Writes outbase.png and outbase.svg.
# Variables (gnuplot -e "name=value; ..."):
#   datafile, outbase     required: input CSV and output path without extension
#   title, xlabel, ylabel optional strings (the labels should carry units)
#   logx, logy            optional, 1 for a logarithmic axis
#   points                optional, 0 for lines with a mark every twelfth row only
#   fitfile               optional CSV with the columns of datafile: a fitted
#                         line per series (its points), drawn dashed in the
#                         series' colour; the data are then drawn as marks only
#   paperfile             optional CSV of a paper's series (first column x, each
#                         other column one series), drawn dashed in the colours
#                         after ours: on our axes, or with paperpanel=1 in a
#                         panel of its own below ours (other units, other x)
#   papertitle, paperxlabel, paperylabel, paperlogy   that panel's title, labels
#                         (default: ours) and logarithmic y (default 0)
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
if (!exists("fitfile")) fitfile = ""
if (!exists("paperfile")) paperfile = ""
if (!exists("paperpanel")) paperpanel = 0
if (!exists("papertitle")) papertitle = ""
if (!exists("paperxlabel")) paperxlabel = xlabel
if (!exists("paperylabel")) paperylabel = ylabel
if (!exists("paperlogy")) paperlogy = 0

# fitfile and paperfile name files of the suite folder (results_chart.c sets suitedir)
if (!exists("suitedir")) suitedir = ""
if (fitfile ne "" && fitfile[1:1] ne "/") fitfile = suitedir.fitfile
if (paperfile ne "" && paperfile[1:1] ne "/") paperfile = suitedir.paperfile

# the palette beside this script
tb_dir = ""
do for [k = strlen(ARG0):1:-1] { if (tb_dir eq "" && ARG0[k:k] eq "/") { tb_dir = ARG0[1:k] } }
load tb_dir."palette.gp"

set datafile separator comma
# the number of our series: the paper's take the linetypes after them
stats datafile skip 1 using 1 nooutput
nours = STATS_columns - 1
# points=0 (long series): lines with a mark every twelfth of the rows, so the
# series still differ by marker
nrows = STATS_records
style = points ? "linespoints" : \
        sprintf("linespoints pointinterval %d", nrows > 24 ? int(nrows / 12) : 1)
if (fitfile ne "") { style = "points" }
fitkey = (fitfile ne "") ? "dashed: least-squares line" : ""
width = 1000; height = paperpanel ? 1100 : 620

do for [t = 1:2] {
  if (t == 1) {
    # pngcairo draws smoother lines; gnuplot-nox builds may only have png (libgd).
    if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
      set terminal pngcairo size width,height noenhanced
    } else {
      set terminal png size width,height noenhanced
    }
    set output outbase.".png"
  } else {
    set terminal svg size width,height dynamic noenhanced
    set output outbase.".svg"
  }
  if (paperpanel) {
    set multiplot layout 2,1
    # both panels the same width, the keys at the right
    set lmargin at screen 0.1
    set rmargin at screen 0.7
  }
  set title title noenhanced
  set xlabel xlabel noenhanced
  set ylabel ylabel noenhanced
  set grid
  if (logx) { set logscale x } else { unset logscale x }
  if (logy) { set logscale y } else { unset logscale y }
  if (paperfile ne "" && !paperpanel) {
    plot for [i = 2:*] datafile using 1:i with @style linetype (i - 1) title columnheader(i), \
         for [i = 2:*] paperfile using 1:i with linespoints linetype (nours + i - 1) dashtype 2 \
           title columnheader(i)
  } else {
    if (fitfile ne "") {
      plot for [i = 2:*] datafile using 1:i with @style linetype (i - 1) title columnheader(i), \
           for [i = 2:*] fitfile using 1:i with lines linetype (i - 1) dashtype 2 notitle, \
           NaN with lines linetype tb_ncolours dashtype 2 title fitkey
    } else {
      plot for [i = 2:*] datafile using 1:i with @style linetype (i - 1) title columnheader(i)
    }
  }
  if (paperpanel) {
    set title papertitle noenhanced
    set xlabel paperxlabel noenhanced
    set ylabel paperylabel noenhanced
    if (paperlogy) { set logscale y } else { unset logscale y }
    plot for [i = 2:*] paperfile using 1:i with linespoints linetype (nours + i - 1) dashtype 2 \
      title columnheader(i)
    unset multiplot
  }
  unset output
}
