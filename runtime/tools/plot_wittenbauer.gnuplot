# plot_wittenbauer.gnuplot: Wittenbauer's diagram (Paul §6.9.3), the kinetic energy T of a
# one-DOF machine against its generalized inertia I over a cycle, with the two rays from the
# origin tangent to the curve: their slopes are w_max^2/2 and w_min^2/2. From the CSV that
# `mechgen_balance wittenbauer --csv ... --diagram-csv D.csv` writes (columns angle_deg, I, T).
#
#   gnuplot -e "csv='out/D.csv'; png='out/wittenbauer.png'" runtime/tools/plot_wittenbauer.gnuplot
#   gnuplot -e "csv='out/D.csv'; svg='out/wittenbauer.svg'" runtime/tools/plot_wittenbauer.gnuplot
#
# Left: the whole diagram with the origin (the rays are nearly one line when the speed is
# steady); right: the curve close up with the tangent rays. Needs gnuplot >= 5 with pngcairo
# (png) or the svg terminal.
if (!exists("csv")) {
  print "usage: gnuplot -e \"csv='D.csv'; png='wittenbauer.png'\" plot_wittenbauer.gnuplot"
  exit
}
if (!exists("png") && !exists("svg")) { png = csv . ".png" }
set datafile separator ","
set datafile columnheaders
stats csv using ($3 / $2) name "S" nooutput
stats csv using 2 name "I" nooutput
stats csv using 3 name "T" nooutput
w_max = sqrt(2 * S_max)
w_min = sqrt(2 * S_min)
if (exists("png")) {
  set terminal pngcairo size 1100,500 noenhanced font ",10"
  set output png
} else {
  set terminal svg size 1100,500 noenhanced dynamic
  set output svg
}
set grid
set xlabel "generalized inertia I [kg m^2]"
set ylabel "kinetic energy T [J]"
set key left top
set multiplot layout 1,2 title sprintf("Wittenbauer: %s   w_max = %.6g rad/s, w_min = %.6g rad/s, C_s = %.4g", \
    csv, w_max, w_min, 2 * (w_max - w_min) / (w_max + w_min))
set xrange [0:I_max * 1.05]
set yrange [0:T_max * 1.05]
plot S_max * x with lines dashtype 2 title "slope w_max^2/2", \
     S_min * x with lines dashtype 3 title "slope w_min^2/2", \
     csv using 2:3 with lines lw 2 title "T(I) over the cycle"
dI = I_max - I_min
dT = T_max - T_min
set xrange [I_min - 0.1 * dI : I_max + 0.1 * dI]
set yrange [T_min - 0.1 * dT : T_max + 0.1 * dT]
plot S_max * x with lines dashtype 2 title "tangent ray, w_max", \
     S_min * x with lines dashtype 3 title "tangent ray, w_min", \
     csv using 2:3 with lines lw 2 title "T(I)"
unset multiplot
