# plot_engine.gnuplot: the charts of an engine model from the CSVs its <model>_engine command
# writes (runtime/tools/engine_main.cc). tools/engine_charts.sh runs them all.
#
#   gnuplot -e "chart='torque'; csv='cycle.csv'; png='torque.png'" tools/plot_engine.gnuplot
#
# chart:
#   torque       (cycle CSV) T_gas, T_inertia, T_total (N m on the crank, CCW +) against the
#                crank angle (deg), with the mean of T_total
#   polar        (cycle CSV) polar diagram of the load of rod 1 on crank pin 1 in the crank's
#                frame (pin_1_u along the throw, pin_1_v 90 deg ahead; N)
#   bearings     (cycle CSV) polar diagrams in the fixed frame of the main bearing load (the
#                crank on the frame: -F_O) and of wrist pin 1 (rod 1 on piston 1), in kN
#   shaking      (cycle CSV of a model with `shaking`) polar diagram of the shaking force on
#                the frame, shake_F_x against shake_F_y (N, fixed frame)
#   shaking_angle  the same components against the crank angle
#   loop         (flywheel --loop CSV) the energy loop E(theta) = integral of (T - T_mean) (J)
#   cs           (flywheel --sweep CSV) C_s against the flywheel inertia J_fly: energy loop
#                and simulation
#   wittenbauer  (flywheel --wittenbauer CSV) kinetic energy T_kin against I(theta) over the
#                steady cycle (Paul 6.9.3)
#   runup        (runup CSV) crank speed (rpm) against time
# title: optional text for the chart's title. Needs gnuplot >= 5 with pngcairo.
if (!exists("chart") || !exists("csv")) {
  print "usage: gnuplot -e \"chart='torque'; csv='cycle.csv'; png='out.png'\" plot_engine.gnuplot"
  exit
}
if (!exists("png")) { png = csv . "." . chart . ".png" }
if (!exists("title")) { title = "" }
set terminal pngcairo size 900,560 font "sans,11" noenhanced
set output png
set datafile separator ","
set key autotitle columnhead
set grid
set title title

if (chart eq "torque") {
  stats csv using 4 name "T" nooutput
  set xlabel "crank angle (deg)"
  set ylabel "torque on the crank (N m, CCW +)"
  set xrange [0:*]
  plot csv using 1:2 with lines lw 1.5 title "gas", \
       csv using 1:3 with lines lw 1.5 title "inertia", \
       csv using 1:4 with lines lw 2 lc rgb "black" title "total", \
       T_mean with lines dt 2 lc rgb "black" title sprintf("mean %.1f N m", T_mean)
}
if (chart eq "polar") {
  set size ratio -1
  set xlabel "along the throw, u (N)"
  set ylabel "90 deg ahead of the throw, v (N)"
  set xzeroaxis lt -1
  set yzeroaxis lt -1
  header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
  cu = 0
  cv = 0
  do for [i = 1:words(header)] {
    if (word(header, i) eq "pin_1_u") { cu = i }
    if (word(header, i) eq "pin_1_v") { cv = i }
  }
  plot csv using cu:cv with lines lw 1.5 title "load of rod 1 on crank pin 1 (crank's frame)", \
       "+" using (0):(0) with points pt 7 ps 1 lc rgb "black" notitle
}
if (chart eq "bearings") {
  set terminal pngcairo size 900,820 font "sans,11" noenhanced
  set output png
  header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
  ox = 0; oy = 0; wx = 0; wy = 0
  do for [i = 1:words(header)] {
    if (word(header, i) eq "F_O_x") { ox = i }
    if (word(header, i) eq "F_O_y") { oy = i }
    if (word(header, i) eq "wrist_1_x") { wx = i }
    if (word(header, i) eq "wrist_1_y") { wy = i }
  }
  set multiplot layout 2,1 title title
  set title "main bearing: load of the crank on the frame"
  set size ratio -1
  set xlabel "x (kN)"
  set ylabel "y (kN)"
  set xzeroaxis lt -1
  set yzeroaxis lt -1
  plot csv using (-column(ox) / 1000):(-column(oy) / 1000) with lines lw 1.5 notitle, \
       "+" using (0):(0) with points pt 7 ps 1 lc rgb "black" notitle
  set title "wrist pin 1: load of rod 1 on piston 1"
  plot csv using (column(wx) / 1000):(column(wy) / 1000) with lines lw 1.5 lc rgb "#009e73" notitle, \
       "+" using (0):(0) with points pt 7 ps 1 lc rgb "black" notitle
  unset multiplot
}
if (chart eq "shaking") {
  set size ratio -1
  set xlabel "shaking force F_x (N)"
  set ylabel "shaking force F_y (N)"
  set xzeroaxis lt -1
  set yzeroaxis lt -1
  header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
  cx = 0
  cy = 0
  do for [i = 1:words(header)] {
    if (word(header, i) eq "shake_F_x") { cx = i }
    if (word(header, i) eq "shake_F_y") { cy = i }
  }
  plot csv using cx:cy with lines lw 1.5 title "shaking force on the frame over the cycle", \
       "+" using (0):(0) with points pt 7 ps 1 lc rgb "black" notitle
}
if (chart eq "shaking_angle") {
  header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
  cx = 0
  cy = 0
  cm = 0
  do for [i = 1:words(header)] {
    if (word(header, i) eq "shake_F_x") { cx = i }
    if (word(header, i) eq "shake_F_y") { cy = i }
    if (word(header, i) eq "shake_M") { cm = i }
  }
  set xlabel "crank angle (deg)"
  set ylabel "shaking force on the frame (N)"
  plot csv using 1:cx with lines lw 1.5 title "F_x", csv using 1:cy with lines lw 1.5 title "F_y"
}
if (chart eq "loop") {
  set xlabel "crank angle (deg)"
  set ylabel "E = integral of (T - T_mean) dtheta (J)"
  set y2label "torque (N m)"
  set y2tics
  plot csv using 1:4 with lines lw 2 title "energy loop E", \
       csv using 1:2 axes x1y2 with lines lw 1 lc rgb "gray" title "T total", \
       csv using 1:3 axes x1y2 with lines dt 2 lc rgb "gray" title "T mean"
}
if (chart eq "cs") {
  set logscale xy
  set xlabel "flywheel J_fly (kg m^2)"
  set ylabel "C_s = (omega_max - omega_min) / omega_mean"
  plot csv using 1:2 with linespoints lw 1.5 title "energy loop", \
       csv using 1:3 with points pt 6 ps 1.5 title "simulated steady cycle"
}
if (chart eq "wittenbauer") {
  set xlabel "generalized inertia I(theta) (kg m^2)"
  set ylabel "kinetic energy T (J)"
  plot csv using 4:5 with lines lw 2 title "steady cycle (Wittenbauer)"
}
if (chart eq "runup") {
  set xlabel "t (s)"
  set ylabel "crank speed (rpm)"
  plot csv using 1:4 with lines lw 1 title "crank speed"
}
