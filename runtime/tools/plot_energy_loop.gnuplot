# plot_energy_loop.gnuplot: the energy loop of a flywheel sizing, from either CSV:
#  - `mechgen_balance flywheel --torque-csv T.csv --energy-csv E.csv` (columns angle_deg,
#    excess_torque [N m] = T_d - T_l, E [J] = its integral from the first angle);
#  - `<model>_flywheel --csv F.csv` / `mechgen flywheel MODEL --csv F.csv` (columns theta_deg,
#    T_req [N m] the required driving torque, T_mean [N m] its mean, E [J]; found by name),
#    which also runs this script itself for --png / --svg.
#
#   gnuplot -e "csv='out/E.csv'; png='out/energy_loop.png'" runtime/tools/plot_energy_loop.gnuplot
#   gnuplot -e "csv='out/E.csv'; svg='out/energy_loop.svg'" runtime/tools/plot_energy_loop.gnuplot
#
# Top: the torque against the crank angle (the excess torque and its loops about zero; or the
# required torque with the mean torque line: the areas between them are the loops). Bottom:
# the excess energy E, with its largest and smallest value marked: their difference is dE,
# the energy the flywheel must absorb (Paul §6.9.2). Needs gnuplot >= 5 with pngcairo (png)
# or the svg terminal.
if (!exists("csv")) {
  print "usage: gnuplot -e \"csv='E.csv'; png='energy_loop.png'\" plot_energy_loop.gnuplot"
  exit
}
if (!exists("png") && !exists("svg")) { png = csv . ".png" }
header = system(sprintf("awk '!/^#/ { print; exit }' '%s'", csv))
machine = strstrt(header, "T_req") > 0
set datafile separator ","
set datafile columnheaders
if (machine) {
  stats csv using "E" name "E" nooutput
  stats csv using "T_mean" name "Tm" nooutput
} else {
  stats csv using 3 name "E" nooutput
}
if (exists("png")) {
  set terminal pngcairo size 900,700 noenhanced font ",10"
  set output png
} else {
  set terminal svg size 900,700 noenhanced dynamic
  set output svg
}
set grid
set autoscale xfix
set xlabel "crank angle [deg]"
set multiplot layout 2,1 title sprintf("energy loop: %s   dE = %.6g J (over the samples)", csv, E_max - E_min)
if (machine) {
  set ylabel "torque on the crank [N m]"
  plot csv using "theta_deg":"T_req":"T_mean" with filledcurves fillstyle transparent solid 0.3 notitle, \
       "" using "theta_deg":"T_req" with lines lw 2 title "required driving torque T_req", \
       "" using "theta_deg":"T_mean" with lines lw 2 dashtype 2 title sprintf("mean (motor) %.6g N m", Tm_mean)
  set ylabel "E [J]"
  set arrow 1 from graph 0, first E_max to graph 1, first E_max nohead dashtype 2
  set arrow 2 from graph 0, first E_min to graph 1, first E_min nohead dashtype 2
  plot csv using "theta_deg":"E" with lines lw 2 title "excess energy E = integral of (T_mean - T_req)", \
       "" using "theta_deg":(column("E") == E_max ? column("E") : 1/0) with points pt 7 ps 1.5 title sprintf("E_max %.6g J", E_max), \
       "" using "theta_deg":(column("E") == E_min ? column("E") : 1/0) with points pt 7 ps 1.5 title sprintf("E_min %.6g J", E_min)
} else {
  set ylabel "T_d - T_l [N m]"
  plot csv using 1:2 with filledcurves y1=0 fillstyle transparent solid 0.3 notitle, \
       "" using 1:2 with lines lw 2 title "excess torque"
  set ylabel "E [J]"
  set arrow 1 from graph 0, first E_max to graph 1, first E_max nohead dashtype 2
  set arrow 2 from graph 0, first E_min to graph 1, first E_min nohead dashtype 2
  plot csv using 1:3 with lines lw 2 title "excess energy E", \
       "" using 1:($3 == E_max ? $3 : 1/0) with points pt 7 ps 1.5 title sprintf("E_max %.6g J", E_max), \
       "" using 1:($3 == E_min ? $3 : 1/0) with points pt 7 ps 1.5 title sprintf("E_min %.6g J", E_min)
}
unset multiplot
