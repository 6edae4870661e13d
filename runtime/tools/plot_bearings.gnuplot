# plot_bearings.gnuplot: the polar diagrams of the ground bearings' loads of a statics sweep,
# from the CSV a <model>_statics command writes (--csv; `--plots PREFIX` runs this script).
#
#   gnuplot -e "csv='out/press.csv'; png='out/press_bearings.png'" runtime/tools/plot_bearings.gnuplot
#   gnuplot -e "csv='out/press.csv'; svg='out/press_bearings.svg'" runtime/tools/plot_bearings.gnuplot
#
# One closed curve per ground bearing J: the tip of the force the ground exerts on the moving
# link at J (columns bearing_<J>_x, bearing_<J>_y, N, fixed frame, without friction) traced
# over the sweep, drawn from the origin at equal scales in x and y; the first row is marked
# with a dot. The curve's title names the link (read from the CSV's comment line of the
# column). Rows whose forces are withheld (status singular: empty cells) leave gaps. Needs
# gnuplot >= 5 with pngcairo (png) or the svg terminal.
if (!exists("csv")) {
  print "usage: gnuplot -e \"csv='statics.csv'; png='bearings.png'\" plot_bearings.gnuplot"
  exit
}
if (!exists("png") && !exists("svg")) { png = csv . "_bearings.png" }

header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
n = words(header)
x_columns = ""
do for [i = 1:n] {
  name = word(header, i)
  if (strstrt(name, "bearing_") == 1 && name[strlen(name) - 1:] eq "_x") {
    x_columns = x_columns . " " . i
  }
}
if (strlen(x_columns) == 0) {
  print "plot_bearings.gnuplot: " . csv . " has no bearing_<J>_x columns (no revolute joint with the ground)"
  exit status 1
}
# "O (on crank)" from the comment line "# bearing_O_x [N]: force of the ground on crank at ...".
joint(c) = word(header, c)[9:strlen(word(header, c)) - 2]
link(c) = system("awk '/^# " . word(header, c) . " / { for (i = 1; i <= NF; ++i) if ($i == \"on\") { print $(i + 1); exit } }' '" . csv . "'")

set datafile separator ","
set datafile columnheaders
# Equal ranges about the origin: the largest component of any bearing's force, 5 % more.
extent = 0
do for [c in x_columns] {
  stats csv using (abs(column(int(c)))):(abs(column(int(c) + 1))) nooutput
  extent = (STATS_max_x > extent) ? STATS_max_x : extent
  extent = (STATS_max_y > extent) ? STATS_max_y : extent
}
extent = (extent > 0) ? 1.05 * extent : 1
if (exists("png")) {
  set terminal pngcairo size 900,900 noenhanced font ",10"
  set output png
} else {
  set terminal svg size 900,900 noenhanced dynamic
  set output svg
}
set title "ground bearings: force of the ground on the moving link, fixed frame, without friction\n(dot: the first row)  " . csv
set size ratio -1
set grid
set key outside right top
set xzeroaxis lt -1
set yzeroaxis lt -1
set xlabel "F_x [N]"
set ylabel "F_y [N]"
set xrange [-extent:extent]
set yrange [-extent:extent]
plot for [c in x_columns] csv using (column(int(c))):(column(int(c) + 1)) \
       with lines lw 2 title joint(int(c)) . " (on " . link(int(c)) . ")", \
     for [c in x_columns] csv every ::0::0 using (column(int(c))):(column(int(c) + 1)) \
       with points pt 7 ps 1 lc rgb "black" notitle
