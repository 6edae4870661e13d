# plot_study_histogram.gnuplot: the histogram of one metric of a design study, from the CSV
# `mechgen study MODEL --study FILE --csv F` writes (docs/studies.md): the samples whose status
# is ok, in `bins` equal bins between their smallest and largest value, with their mean and
# mean +- sigma marked.
#
#   gnuplot -e "csv='out/study.csv'; metric='max_coupler.P.y'; png='out/hist.png'" runtime/tools/plot_study_histogram.gnuplot
#   gnuplot -e "csv='out/study.csv'; metric='peak_drive'; bins=60; svg='out/hist.svg'" runtime/tools/plot_study_histogram.gnuplot
#
# The metric's unit comes from the CSV's comment line "# <metric> [unit]: ...". Without
# `metric`, the first column after the parameters that is not `failures` or `status`. Needs
# gnuplot >= 5 with pngcairo (png) or the svg terminal.
if (!exists("csv")) {
  print "usage: gnuplot -e \"csv='study.csv'; metric='NAME'; png='hist.png'\" plot_study_histogram.gnuplot"
  exit
}
if (!exists("png") && !exists("svg")) { png = csv . ".png" }
if (!exists("bins")) { bins = 40 }

header = system("awk '!/^#/ { print; exit }' '" . csv . "' | tr ',' ' '")
n = words(header)
status_column = 0
do for [i = 1:n] { if (word(header, i) eq "status") { status_column = i } }
if (status_column == 0) { print "plot_study_histogram: " . csv . " has no status column: not a study CSV"; exit status 1 }
if (!exists("metric")) {
  # The last parameter is the column before the first metric; the metrics follow the comment
  # lines in order: take the first metric that is not the failure count.
  metric = system("awk '/^# / && substr($3, 1, 1) == \"[\" && !($3 == \"[model\" && $4 == \"units]:\") && $2 != \"sample\" && $2 != \"failures\" && $2 != \"status\" { print $2; exit }' '" . csv . "'")
}
column = 0
do for [i = 1:n] { if (word(header, i) eq metric) { column = i } }
if (column == 0) { print "plot_study_histogram: no column '" . metric . "' in " . csv . " (columns: " . header . ")"; exit status 1 }
unit = system("awk -F'[][]' -v m='" . metric . "' 'index($0, \"# \" m \" [\") == 1 { print $2; exit }' '" . csv . "'")

set datafile separator ","
set datafile commentschars "#"
ok(x) = (strcol(status_column) eq "ok") ? x : NaN
stats csv using (ok(column(column))) nooutput
if (STATS_records == 0) { print "plot_study_histogram: no ok sample with a value of " . metric; exit status 1 }
lo = STATS_min
hi = STATS_max
width = (hi > lo) ? (hi - lo) / bins : 1
bin(x) = lo + width * (floor((x - lo) / width) + 0.5)

if (exists("png")) { set terminal pngcairo size 900, 560; set output png }
if (exists("svg")) { set terminal svg size 900, 560 dynamic; set output svg }
set title sprintf("%s: %d ok samples, mean %.6g, sigma %.3g (%s)", metric, STATS_records, STATS_mean, STATS_stddev, unit) noenhanced
set xlabel sprintf("%s [%s]", metric, unit) noenhanced
set ylabel "samples"
set yrange [0:*]
set offsets 0, 0, graph 0.05, 0
set style fill solid 0.6 border -1
set boxwidth width
set arrow 1 from STATS_mean, graph 0 to STATS_mean, graph 1 nohead lw 2 lc rgb "black"
set arrow 2 from STATS_mean - STATS_stddev, graph 0 to STATS_mean - STATS_stddev, graph 1 nohead dt 2 lc rgb "black"
set arrow 3 from STATS_mean + STATS_stddev, graph 0 to STATS_mean + STATS_stddev, graph 1 nohead dt 2 lc rgb "black"
plot csv using (bin(ok(column(column)))):(1.0) smooth frequency with boxes lc rgb "#4477aa" notitle
