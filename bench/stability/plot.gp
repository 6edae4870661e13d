# gnuplot -e "csv='results/stability.csv'; case='toggle'; out='results/toggle.svg'" plot.gp
# Three panels: relative error of phi, K and L against the distance to the singular
# configuration, one line per method. Missing points: the method returned nothing (a
# refusal such as 'singular', or no convergence). Errors below 1e-17 are drawn at 1e-17.
set terminal svg size 1200,460 dynamic font "sans,11" background rgb "white" noenhanced
set output out
set datafile separator ","
set logscale xy
set format x "1e%L"
set format y "1e%L"
set xrange [2e-11:0.5] reverse
set yrange [1e-17:1e8]
set grid
set key top right font ",8" spacing 0.85 noenhanced
methods = "closed_form newton_raw continuation continuation_pass ceres_analytic ceres_autodiff ceres_numeric finite_diff"
filter(m, col) = sprintf("< awk -F, '$1==\"%s\" && $2==\"%s\" {v=$%d; if (v+0 < 1e-17 && v != \"nan\") v=1e-17; print $3\",\"v}' %s", case, m, col, csv)
titles = "phi (rad) K (relative) L (relative)"
set multiplot layout 1,3 title sprintf("mechgen stability study: %s", case)
do for [i=1:3] {
  set title "error of ".word(titles, 2*i-1)." ".word(titles, 2*i)
  set xlabel "distance to the singular input (rad)"
  if (i > 1) { unset key }
  plot for [m in methods] filter(m, 5+i) using 1:2 with linespoints pointsize 0.6 title m
}
unset multiplot
