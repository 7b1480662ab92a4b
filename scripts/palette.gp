# The palette of every chart (loaded by every scripts/chart_*.gp): 14 colours
# that stay apart on white, each with its own marker, set as linetypes 1-14
# so that series i of a plot is drawn in colour i with marker i. A chart
# with n series uses linetypes 1..n: no two series of a chart share a colour
# (tests/test_results.c checks the colours are distinct and every script
# loads this file). Scripts name a colour by its index: tb_colours[k].
# Also: the key outside the data area, at the right.
array tb_colours[14] = ["#4363d8", "#e6194b", "#3cb44b", "#f58231", "#911eb4", "#0099c6", \
                        "#f032e6", "#469990", "#9a6324", "#000075", "#808000", "#800000", \
                        "#808080", "#000000"]
array tb_points[14] = [7, 5, 9, 11, 13, 15, 6, 4, 8, 10, 12, 14, 1, 2]
tb_ncolours = |tb_colours|
do for [k = 1:tb_ncolours] {
  set linetype k linecolor rgb tb_colours[k] linewidth 2 pointtype tb_points[k] \
    pointsize 1.3 dashtype solid
}
set linetype cycle tb_ncolours
set key outside right top vertical Left reverse noenhanced
