# plot_statics.gnuplot: the driving forces and the reaction magnitudes of a statics sweep
# against the first input, from the CSV a <model>_statics command writes (--csv).
#
#   gnuplot -e "csv='out/press.csv'; png='out/press.png'" runtime/tools/plot_statics.gnuplot
#   gnuplot -e "csv='out/press.csv'; svg='out/press_plot.svg'" runtime/tools/plot_statics.gnuplot
#
# Top: every drive_* column (the driving torque or force without friction, drive_<q>, and
# with friction to run the input in +q and in -q, drive_<q>_plus and drive_<q>_minus), with the self-locking rows (self_locking_* = 1: the dead zones)
# marked on the axis. Bottom: every F_<joint>_mag column (|reaction force| at each joint,
# without friction). The x axis is the CSV's first column, in degrees when its name says it
# is an angle (theta_*, psi_*; set deg=0 or deg=1 to override). Rows whose forces are
# withheld (status singular: empty cells) leave gaps. Needs gnuplot >= 5 with pngcairo
# (png) or the svg terminal.
if (!exists("csv")) {
  print "usage: gnuplot -e \"csv='statics.csv'; png='statics.png'\" plot_statics.gnuplot"
  exit
}
if (!exists("png") && !exists("svg")) { png = csv . ".png" }

header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
n = words(header)
x_name = word(header, 1)
# The drive's unit from the CSV's comment line "# drive_<q> [N m]: ...".
drive_unit = system("awk -F'[][]' '/^# drive_/ { print $2; exit }' '" . csv . "'")
if (!exists("deg")) { deg = (strstrt(x_name, "theta") == 1 || strstrt(x_name, "psi") == 1) ? 1 : 0 }

drive_columns = ""
magnitude_columns = ""
lock_column = 0
do for [i = 1:n] {
  name = word(header, i)
  if (strstrt(name, "drive_") == 1) { drive_columns = drive_columns . " " . i }
  if (strlen(name) > 6 && strstrt(name, "F_") == 1 && name[strlen(name) - 3:] eq "_mag") {
    magnitude_columns = magnitude_columns . " " . i
  }
  if (lock_column == 0 && strstrt(name, "self_locking_") == 1) { lock_column = i }
}

set datafile separator ","
set datafile columnheaders
if (exists("png")) {
  set terminal pngcairo size 1000,800 noenhanced font ",10"
  set output png
} else {
  set terminal svg size 1000,800 noenhanced dynamic
  set output svg
}
x(c) = deg ? c * 180 / pi : c
set key outside right top
set grid
set autoscale xfix
set multiplot layout 2,1 title "statics: " . csv
set xlabel x_name . (deg ? " [deg]" : "")
set ylabel "driving torque or force [" . drive_unit . "]"
if (lock_column > 0) {
  plot for [c in drive_columns] csv using (x(column(1))):(column(int(c)))  \
         with lines lw 2 title word(header, int(c)), \
       csv using (x(column(1))):(column(lock_column) == 1 ? 0 : NaN)  \
         with points pt 7 ps 0.4 lc rgb "#c00000" title "self-locking"
} else {
  plot for [c in drive_columns] csv using (x(column(1))):(column(int(c)))  \
         with lines lw 2 title word(header, int(c))
}
set ylabel "|reaction force| [N]"
if (strlen(magnitude_columns) > 0) {
  plot for [c in magnitude_columns] csv using (x(column(1))):(column(int(c)))  \
         with lines lw 2 title word(header, int(c))
}
unset multiplot
