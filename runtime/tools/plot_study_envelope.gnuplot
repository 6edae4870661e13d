# plot_study_envelope.gnuplot: the envelope of a point's path over a tolerance study, from the
# CSV `mechgen study MODEL --study FILE --envelope-csv F` writes (docs/studies.md): against the
# input (in degrees when it is an angle: set deg=0 for a slide), the first-order sigma of the
# point's x and y (lines, from the generated dr_P/dp) and the Monte-Carlo's sigma with its 95 %
# interval (points with error bars). Where the points leave the lines, the first order fails.
#
#   gnuplot -e "csv='out/envelope.csv'; png='out/envelope.png'" runtime/tools/plot_study_envelope.gnuplot
#
# Needs gnuplot >= 5 with pngcairo (png) or the svg terminal.
if (!exists("csv")) {
  print "usage: gnuplot -e \"csv='envelope.csv'; png='envelope.png'\" plot_study_envelope.gnuplot"
  exit
}
if (!exists("png") && !exists("svg")) { png = csv . ".png" }
header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
if (word(header, 5) ne "fo_sigma_x" || word(header, 10) ne "mc_sigma_x") {
  print "plot_study_envelope: " . csv . " is not a study's envelope CSV (header: " . header . ")"
  exit status 1
}
input = word(header, 2)
point = system("awk '/^# mechgen study envelope of / { print $6; exit }' '" . csv . "' | tr -d ','")
if (!exists("deg")) { deg = (strstrt(input, "theta") == 1 || strstrt(input, "psi") == 1) ? 1 : 0 }
scale = deg ? 180 / pi : 1

set datafile separator ","
if (exists("png")) { set terminal pngcairo size 900, 560; set output png }
if (exists("svg")) { set terminal svg size 900, 560 dynamic; set output svg }
set title sprintf("envelope of %s: sigma of x and y, first order (lines) and Monte-Carlo with 95 %% intervals", point) noenhanced
set xlabel input . (deg ? " [deg]" : "") noenhanced
set ylabel "sigma [model length]"
set key below horizontal
set autoscale xfix
plot csv using ($2 * scale):5 with lines lw 2 lc rgb "#4477aa" title "x, first order", \
     ''  using ($2 * scale):10:11:12 with yerrorbars pt 7 ps 0.5 lc rgb "#4477aa" title "x, Monte-Carlo", \
     ''  using ($2 * scale):6 with lines lw 2 lc rgb "#ee6677" title "y, first order", \
     ''  using ($2 * scale):13:14:15 with yerrorbars pt 7 ps 0.5 lc rgb "#ee6677" title "y, Monte-Carlo"
