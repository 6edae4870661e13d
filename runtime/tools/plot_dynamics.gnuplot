# plot_dynamics.gnuplot: a simulated transient against time, from the CSV a <model>_simulate
# command writes (--csv).
#
#   gnuplot -e "csv='out/motor.csv'; png='out/motor.png'" runtime/tools/plot_dynamics.gnuplot
#   gnuplot -e "csv='out/motor.csv'; svg='out/motor.svg'" runtime/tools/plot_dynamics.gnuplot
#
# Four panels against t (s): (1) the first input q (degrees for an angle: its name begins
# with theta or psi; set deg=0 or deg=1 to override) and its speed q_dot (rad/s or m/s, right
# axis); (2) every Q_* column, the generalized applied force (N m for an angle input, CCW +);
# (3) the energies T, V, E = T + V and E - W_nc (J; E - W_nc is constant up to the
# integrator's error: the energy balance); (4) every F_<joint>_mag column (|reaction| at each
# revolute joint, N, inertia forces included). Rows whose reactions are withheld (a dead point)
# leave gaps. Needs gnuplot >= 5 with pngcairo (png) or the svg terminal.
if (!exists("csv")) {
  print "usage: gnuplot -e \"csv='simulate.csv'; png='simulate.png'\" plot_dynamics.gnuplot"
  exit
}
if (!exists("png") && !exists("svg")) { png = csv . ".png" }

header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
n = words(header)
q_name = word(header, 2)
if (!exists("deg")) { deg = (strstrt(q_name, "theta") == 1 || strstrt(q_name, "psi") == 1) ? 1 : 0 }

q_column = 2
qd_column = 0
Q_columns = ""
magnitude_columns = ""
T_column = 0
V_column = 0
E_column = 0
W_column = 0
do for [i = 1:n] {
  name = word(header, i)
  if (name eq q_name . "_dot") { qd_column = i }
  if (strstrt(name, "Q_") == 1) { Q_columns = Q_columns . " " . i }
  if (name eq "T") { T_column = i }
  if (name eq "V") { V_column = i }
  if (name eq "E") { E_column = i }
  if (name eq "W_nc") { W_column = i }
  if (strlen(name) > 6 && strstrt(name, "F_") == 1 && name[strlen(name) - 3:] eq "_mag") {
    magnitude_columns = magnitude_columns . " " . i
  }
}

set datafile separator ","
set datafile columnheaders
if (exists("png")) {
  set terminal pngcairo size 1000,1100 noenhanced font ",10"
  set output png
} else {
  set terminal svg size 1000,1100 noenhanced dynamic
  set output svg
}
qscale = deg ? 180 / pi : 1
set key outside right top
set grid
set autoscale xfix
set multiplot layout 4,1 title "dynamics: " . csv

set ylabel q_name . (deg ? " (deg)" : "")
set y2label q_name . "_dot"
set ytics nomirror
set y2tics
plot csv using 1:(column(q_column) * qscale) with lines lw 1.5 title q_name, \
     csv using 1:(column(qd_column)) axes x1y2 with lines lw 1.5 title q_name . "_dot"
unset y2tics
unset y2label
set ytics mirror

set ylabel "Q (N m or N)"
plot for [c in Q_columns] csv using 1:(column(int(c))) with lines lw 1.5 title word(header, int(c))

set ylabel "energy (J)"
plot csv using 1:(column(T_column)) with lines title "T", \
     csv using 1:(column(V_column)) with lines title "V", \
     csv using 1:(column(E_column)) with lines title "E = T + V", \
     csv using 1:(column(E_column) - column(W_column)) with lines dt 2 title "E - W_nc"

set xlabel "t (s)"
set ylabel "|reaction| (N)"
if (strlen(magnitude_columns) > 0) {
  plot for [c in magnitude_columns] csv using 1:(column(int(c))) with lines title word(header, int(c))
} else {
  set label 1 "no reactions in this model" at graph 0.5, 0.5 center
  plot NaN notitle
}
unset multiplot
