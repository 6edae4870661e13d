#!/usr/bin/env bash
# `mechgen study MODEL --study FILE` (runtime/tools/study_main.cc, compiled once in a private
# cache): the CSV of 1 and 2 threads byte for byte the same; its header (comment lines with
# units, then sample, the parameters, the metrics, status) and one row per sample; the
# tolerance CSV; a study file with an error: exit 2, one line FILE:LINE:COLUMN, no CSV; a study
# that does not fit the model: exit 1, no CSV; a bad option: exit 2, one line; the histogram
# and scatter scripts draw PNGs from the CSV and the envelope script from the envelope CSV
# (when gnuplot is installed).
# usage: study_command_test.sh <mechgen> <source dir>
set -uo pipefail
mechgen=$(realpath "$1") source_dir=$(realpath "$2")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
cd "$root" || exit 1
export MECHGEN_CACHE_DIR=$root/cache
cp "$source_dir/models/fourbar.yaml" fourbar.yaml
cp "$source_dir/models/fourbar.study.yaml" study.yaml
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { echo "ok $*"; }

"$mechgen" study fourbar.yaml --study study.yaml --threads 1 --csv one.csv --tolerance-csv tol.csv \
  --envelope-csv env.csv > one.out 2> one.err
status=$?
[ "$status" -eq 0 ] || fail "1 thread: exit status $status: $(cat one.err)"
"$mechgen" study fourbar.yaml --study study.yaml --threads 2 --csv two.csv --quiet > two.out 2> two.err
status=$?
[ "$status" -eq 0 ] || fail "2 threads: exit status $status: $(cat two.err)"
grep -q "compiling" two.err && fail "the second run compiled again"
if cmp -s one.csv two.csv; then ok "1 and 2 threads: the same bytes"; else fail "1 and 2 threads differ"; fi
samples=$(awk '/^count:/ { print $2 }' study.yaml)
rows=$(grep -v '^#' one.csv | tail -n +2 | wc -l)
[ "$rows" -eq "$samples" ] || fail "$rows rows, expected $samples"
header=$(grep -v '^#' one.csv | head -1)
case "$header" in sample,a,b,c,d,*,status) ok "header $header" ;; *) fail "header $header" ;; esac
grep -q '^# a \[model units\]' one.csv || fail "no unit line for the parameter a"
grep -q '^# min_transmission_angle \[rad\]' one.csv || fail "no unit line for min_transmission_angle"
# Every number with 17 significant digits (%.17g: trailing zeros dropped, so most, not all).
awk -F, '!/^#/ && ++n > 1 { for (i = 2; i <= 5; ++i) { s = $i; sub(/e.*/, "", s); gsub(/[-.]/, "", s);
  sub(/^0+/, "", s); total++; full += length(s) == 17 } } END { exit !(total > 0 && full > 0.9 * total) }' one.csv ||
  fail "parameters not written with %.17g: $(grep -v '^#' one.csv | sed -n 2p)"
grep -q '^metric,unit,nominal,fo_sigma,fo_worst,clearance,mc_n' tol.csv || fail "tolerance CSV header: $(grep -v '^#' tol.csv | head -1)"
grep -q 'agrees' one.out || fail "no agreeing metric in the tolerance analysis: $(cat one.out)"
steps=$(awk '/^steps:/ { print $2 }' study.yaml)
[ "$(grep -v '^#' env.csv | tail -n +2 | wc -l)" -eq $((steps + 1)) ] || fail "envelope: not one line per row"
grep -q '^row,theta_crank,x_nominal,y_nominal,fo_sigma_x' env.csv || fail "envelope header: $(grep -v '^#' env.csv | head -1)"
grep -q '^envelope of coupler.P: ' one.out || fail "no envelope summary: $(cat one.out)"

# A study file with an error: one line file:line:column, exit 2, no CSV.
sed 's/^method: monte_carlo/method: montecarlo/' study.yaml > bad.yaml
"$mechgen" study fourbar.yaml --study bad.yaml --csv bad.csv > bad.out 2> bad.err
status=$?
[ "$status" -eq 2 ] || fail "bad study: exit status $status"
grep -Eq '^bad\.yaml:[0-9]+:9: error: method: expected grid, list, lhs or monte_carlo' bad.err || fail "bad study: $(cat bad.err)"
[ "$(grep -c '' bad.err)" -eq 1 ] || fail "bad study: more than one line: $(cat bad.err)"
[ -e bad.csv ] && fail "bad study: a CSV was written"
# A study that does not fit the model: exit 1, its place, no CSV.
sed 's/^  b: /  bb: /' study.yaml > misfit.yaml
"$mechgen" study fourbar.yaml --study misfit.yaml --csv misfit.csv > misfit.out 2> misfit.err
status=$?
[ "$status" -eq 1 ] || fail "misfit: exit status $status"
grep -Eq "^misfit\.yaml:[0-9]+:3: error: no parameter 'bb' in the model fourbar" misfit.err || fail "misfit: $(cat misfit.err)"
[ -e misfit.csv ] && fail "misfit: a CSV was written"
# A bad option: exit 2, one line.
"$mechgen" study fourbar.yaml --study study.yaml --threads 0 > opt.out 2> opt.err
status=$?
[ "$status" -eq 2 ] || fail "--threads 0: exit status $status"
[ "$(grep -c '' opt.err)" -eq 1 ] || fail "--threads 0: not one line: $(cat opt.err)"

if command -v gnuplot > /dev/null; then
  gnuplot -e "csv='one.csv'; metric='min_transmission_angle'; png='hist.png'" \
    "$source_dir/runtime/tools/plot_study_histogram.gnuplot" 2> hist.err || fail "histogram: $(cat hist.err)"
  [ -s hist.png ] || fail "histogram: no PNG"
  gnuplot -e "csv='one.csv'; metric='nope'; png='nope.png'" "$source_dir/runtime/tools/plot_study_histogram.gnuplot" \
    2> nope.err && fail "histogram of no such column: exit 0"
  grep -q "no column 'nope'" nope.err || fail "histogram of no such column: $(cat nope.err)"
  gnuplot -e "csv='one.csv'; metric='min_transmission_angle'; parameter='c'; png='scatter.png'" \
    "$source_dir/runtime/tools/plot_study_scatter.gnuplot" 2> scatter.err || fail "scatter: $(cat scatter.err)"
  [ -s scatter.png ] || fail "scatter: no PNG"
  gnuplot -e "csv='env.csv'; png='env.png'" "$source_dir/runtime/tools/plot_study_envelope.gnuplot" 2> env.err ||
    fail "envelope plot: $(cat env.err)"
  [ -s env.png ] || fail "envelope plot: no PNG"
  gnuplot -e "csv='one.csv'; png='notenv.png'" "$source_dir/runtime/tools/plot_study_envelope.gnuplot" 2> notenv.err &&
    fail "envelope plot of the samples' CSV: exit 0"
fi

[ "$failures" -eq 0 ] && echo "all ok" || echo "$failures failure(s)"
exit $((failures > 0))
