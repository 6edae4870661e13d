# plot_study_scatter.gnuplot: one metric of a design study against one of its parameters, from
# the CSV `mechgen study MODEL --study FILE --csv F` writes (docs/studies.md): a point per
# sample whose status is ok; samples that failed (rows_failed, not_assembled) marked on the
# x axis.
#
#   gnuplot -e "csv='out/study.csv'; metric='min_transmission_angle'; parameter='c'; png='out/scatter.png'" \
#       runtime/tools/plot_study_scatter.gnuplot
#
# Units from the CSV's comment lines. Needs gnuplot >= 5 with pngcairo (png) or the svg terminal.
if (!exists("csv") || !exists("metric") || !exists("parameter")) {
  print "usage: gnuplot -e \"csv='study.csv'; metric='NAME'; parameter='NAME'; png='scatter.png'\" plot_study_scatter.gnuplot"
  exit status 1
}
if (!exists("png") && !exists("svg")) { png = csv . ".png" }
header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
n = words(header)
status_column = 0; metric_column = 0; parameter_column = 0
do for [i = 1:n] {
  if (word(header, i) eq "status") { status_column = i }
  if (word(header, i) eq metric) { metric_column = i }
  if (word(header, i) eq parameter) { parameter_column = i }
}
if (status_column == 0) { print "plot_study_scatter: " . csv . " has no status column: not a study CSV"; exit status 1 }
if (metric_column == 0) { print "plot_study_scatter: no column '" . metric . "' in " . csv . " (columns: " . header . ")"; exit status 1 }
if (parameter_column == 0) { print "plot_study_scatter: no column '" . parameter . "' in " . csv . " (columns: " . header . ")"; exit status 1 }
unit(name) = system("awk -F'[][]' -v m='" . name . "' 'index($0, \"# \" m \" [\") == 1 { print $2; exit }' '" . csv . "'")
metric_unit = unit(metric)
parameter_unit = unit(parameter)

set datafile separator ","
if (exists("png")) { set terminal pngcairo size 900, 560; set output png }
if (exists("svg")) { set terminal svg size 900, 560 dynamic; set output svg }
set title sprintf("%s against %s", metric, parameter) noenhanced
set xlabel sprintf("%s [%s]", parameter, parameter_unit) noenhanced
set ylabel sprintf("%s [%s]", metric, metric_unit) noenhanced
set key below horizontal
set y2range [0:1]
unset y2tics
ok(y) = (strcol(status_column) eq "ok") ? y : NaN
failed(y) = (strcol(status_column) ne "ok") ? y : NaN
plot csv using (column(parameter_column)):(ok(column(metric_column))) with points pt 7 ps 0.4 lc rgb "#4477aa" title "ok samples", \
     ''  using (failed(column(parameter_column))):(0.02) with points pt 2 ps 0.8 lc rgb "#ee6677" axes x1y2 title "failed samples (at the axis)"
