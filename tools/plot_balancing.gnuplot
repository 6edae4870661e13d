# plot_balancing.gnuplot: the balanced four-bar (models/fourbar_balanced.yaml) against its
# unbalanced twin, from the two CSV files tools/fourbar_balancing writes:
#
#   gnuplot -e "dir='out'; pictures='docs/pictures'" tools/plot_balancing.gnuplot
#
# reads dir/fourbar_balancing_{balanced,unbalanced}.csv and writes, in `pictures`:
#   fourbar_balancing_force.png      polar diagram of the shaking force (F_y against F_x, N: the
#                                    tip of the force the frame feels over a crank revolution)
#   fourbar_balancing_moment.png     shaking moment about O2 and driving torque against the crank
#                                    angle (N m, CCW +)
#   fourbar_balancing_reactions.png  bearing loads on the frame at O2 and O4 and the pin forces at
#                                    A and B against the crank angle (N)
# Needs gnuplot >= 5 with the pngcairo terminal.
if (!exists("dir")) {
  print "usage: gnuplot -e \"dir='out'; pictures='docs/pictures'\" plot_balancing.gnuplot"
  exit
}
if (!exists("pictures")) { pictures = dir }
bal = dir . "/fourbar_balancing_balanced.csv"
unb = dir . "/fourbar_balancing_unbalanced.csv"
set datafile separator ","
set key top right box opaque
set grid
set terminal pngcairo size 640,600 font ",10"

set output pictures . "/fourbar_balancing_force.png"
set title "Shaking force on the frame over a crank revolution (polar diagram)"
set xlabel "F_x (N)"
set ylabel "F_y (N)"
set size ratio -1
plot unb using 2:3 with lines lw 2 lc rgb "#c0392b" title "unbalanced", \
     bal using 2:3 with points pt 7 ps 1.2 lc rgb "#2471a3" title "balanced (counterweights): F = 0"
set size noratio

set terminal pngcairo size 800,600 font ",10"
set output pictures . "/fourbar_balancing_moment.png"
set multiplot layout 2,1 title "Balancing trades shaking force against shaking moment and driving torque"
set xrange [0:360]
set xtics 45
set title "Shaking moment about O2"
set xlabel ""
set ylabel "M (N m)"
plot unb using 1:5 with lines lw 2 lc rgb "#c0392b" title "unbalanced", \
     bal using 1:5 with lines lw 2 lc rgb "#2471a3" title "balanced"
set title "Driving torque on the crank (constant speed, kinetostatics)"
set xlabel "crank angle (deg)"
set ylabel "torque (N m)"
plot unb using 1:6 with lines lw 2 lc rgb "#c0392b" title "unbalanced", \
     bal using 1:6 with lines lw 2 lc rgb "#2471a3" title "balanced"
unset multiplot

set output pictures . "/fourbar_balancing_reactions.png"
set multiplot layout 2,1 title "Bearing loads: ground pivots O2, O4 and pins A, B"
set title "Ground bearings (load on the frame)"
set xlabel ""
set ylabel "|force| (N)"
plot unb using 1:9 with lines lw 2 lc rgb "#c0392b" title "O2 unbalanced", \
     bal using 1:9 with lines lw 2 lc rgb "#2471a3" title "O2 balanced", \
     unb using 1:12 with lines lw 2 dt 2 lc rgb "#e67e22" title "O4 unbalanced", \
     bal using 1:12 with lines lw 2 dt 2 lc rgb "#17a589" title "O4 balanced (= O2: F = 0)"
set title "Moving pins"
set xlabel "crank angle (deg)"
set ylabel "|force| (N)"
plot unb using 1:13 with lines lw 2 lc rgb "#c0392b" title "A unbalanced", \
     bal using 1:13 with lines lw 2 lc rgb "#2471a3" title "A balanced", \
     unb using 1:14 with lines lw 2 dt 2 lc rgb "#e67e22" title "B unbalanced", \
     bal using 1:14 with lines lw 2 dt 2 lc rgb "#17a589" title "B balanced"
unset multiplot
unset output
