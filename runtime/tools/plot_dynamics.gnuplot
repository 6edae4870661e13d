# plot_dynamics.gnuplot: a simulated transient against time, from the CSV a <model>_simulate
# command writes (--csv).
#
#   gnuplot -e "csv='out/motor.csv'; png='out/motor.png'" runtime/tools/plot_dynamics.gnuplot
#   gnuplot -e "csv='out/motor.csv'; svg='out/motor.svg'" runtime/tools/plot_dynamics.gnuplot
#
# Four panels: (1) the first input q (degrees for an angle: its name begins with theta or psi;
# set deg=0 or deg=1 to override) and its speed q_dot (rad/s or m/s, right axis); (2) in a run
# with motion generators (--drive: the CSV has lambda_* columns) the actuator forces lambda_<q>
# the laws need (N m on the input link CCW +, or N along the slide), otherwise every Q_*
# column, the generalized applied force (N m for an angle input, CCW +); (3) the energies T,
# V, E = T + V and E - W_nc (J; E - W_nc is constant up to the integrator's error: the energy
# balance; with drives E - W_nc - W_act, the column balance); (4) every F_<joint>_mag column
# (|reaction| at each revolute joint, N, inertia forces included). The x axis is t (s), or, in
# a run with drives, the first input's angle (deg, as it accumulates) where that input turns
# at least a full turn and only forward (a crank driven at speed: the periodic motion, whose
# torque and bearing loads read against the crank angle); set x_angle=0 or x_angle=1 to choose. Rows whose
# reactions or lambdas are withheld (a dead point) leave gaps. Needs gnuplot >= 5 with
# pngcairo (png) or the svg terminal.
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
lambda_columns = ""
balance_column = 0
magnitude_columns = ""
T_column = 0
V_column = 0
E_column = 0
W_column = 0
do for [i = 1:n] {
  name = word(header, i)
  if (name eq q_name . "_dot") { qd_column = i }
  if (strstrt(name, "Q_") == 1) { Q_columns = Q_columns . " " . i }
  if (strstrt(name, "lambda_") == 1) { lambda_columns = lambda_columns . " " . i }
  if (name eq "balance") { balance_column = i }
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

# Against the crank angle in a run with drives when the first input is an angle that turns a
# full turn or more, never backwards (its speed never negative); free runs against t.
if (!exists("x_angle")) {
  x_angle = 0
  if (deg && qd_column > 0 && strlen(lambda_columns) > 0) {
    stats csv using q_column name "Q0" nooutput
    stats csv using qd_column name "QD" nooutput
    x_angle = (Q0_max - Q0_min >= 2 * pi * (1 - 1e-9) && QD_min >= 0) ? 1 : 0
  }
}
x_expr = x_angle ? "(column(q_column) * 180 / pi)" : "(column(1))"
x_label = x_angle ? q_name . " (deg, accumulated)" : "t (s)"

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
# One plot width for the four panels, whatever the keys' widths.
set lmargin at screen 0.09
set rmargin at screen 0.78

if (x_angle) {
  set ylabel q_name . "_dot"
  plot csv using (@x_expr):(column(qd_column)) with lines lw 1.5 title q_name . "_dot"
} else {
  set ylabel q_name . (deg ? " (deg)" : "")
  set y2label q_name . "_dot"
  set ytics nomirror
  set y2tics
  plot csv using 1:(column(q_column) * qscale) with lines lw 1.5 title q_name, \
       csv using 1:(column(qd_column)) axes x1y2 with lines lw 1.5 title q_name . "_dot"
  unset y2tics
  unset y2label
  set ytics mirror
}

if (strlen(lambda_columns) > 0) {
  set ylabel "lambda: actuator force (N m or N)"
  plot for [c in lambda_columns] csv using (@x_expr):(column(int(c))) with lines lw 1.5 title word(header, int(c))
} else {
  set ylabel "Q (N m or N)"
  plot for [c in Q_columns] csv using (@x_expr):(column(int(c))) with lines lw 1.5 title word(header, int(c))
}

set ylabel "energy (J)"
if (balance_column > 0) {
  plot csv using (@x_expr):(column(T_column)) with lines title "T", \
       csv using (@x_expr):(column(V_column)) with lines title "V", \
       csv using (@x_expr):(column(E_column)) with lines title "E = T + V", \
       csv using (@x_expr):(column(balance_column)) with lines dt 2 title "E - W_nc - W_act"
} else {
  plot csv using (@x_expr):(column(T_column)) with lines title "T", \
       csv using (@x_expr):(column(V_column)) with lines title "V", \
       csv using (@x_expr):(column(E_column)) with lines title "E = T + V", \
       csv using (@x_expr):(column(E_column) - column(W_column)) with lines dt 2 title "E - W_nc"
}

set xlabel x_label
set ylabel "|reaction| (N)"
if (strlen(magnitude_columns) > 0) {
  plot for [c in magnitude_columns] csv using (@x_expr):(column(int(c))) with lines title word(header, int(c))
} else {
  set label 1 "no reactions in this model" at graph 0.5, 0.5 center
  set yrange [0:1]
  plot -1 notitle
}
unset multiplot
