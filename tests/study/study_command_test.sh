#!/usr/bin/env bash
# `mechgen study MODEL --study FILE` (runtime/tools/study_main.cc, compiled once in a private
# cache): the CSV of 1 and 2 threads byte for byte the same; its header (comment lines with
# units, then sample, the parameters, the metrics, status) and one row per sample; the
# tolerance CSV; a study file with an error: exit 2, one line FILE:LINE:COLUMN, no CSV; a study
# that does not fit the model: exit 1, no CSV; a bad option: exit 2, one line; the histogram
# and scatter scripts draw PNGs from the CSV and the envelope script from the envelope CSV
# (when gnuplot is installed). The form `mechgen study STUDY.yaml` (the study names its model) gives
# the same bytes; so do 4 threads; a study stopped part way (--stop-after) or killed (SIGKILL) and
# run again resumes from its shards and gives the same bytes; under `mpirun --oversubscribe -np 2`
# (and -np 1; a driver compiled with MPI) the same bytes, also when resumed from the shards of a
# two-rank run (skipped, saying so, only when CMake found no MPI). Hostile study files (a
# directory, a grid beyond 10^8 samples, a metric name with a comma, a key twice) and bad
# --set/--params: exit 2, one line, nothing written; --params and --set move the base of the
# samples; a study of 10^8 samples stopped after one chunk holds that chunk alone. Through the
# model view (issue 43): the outputs of the sweep (with tolerance: true, an envelope and
# design_margin: the tolerance and envelope CSVs too), positions, statics, simulate, engine and
# flywheel analyses and the driven simulation (drive:) the per-model program's bytes at 1 and 2
# threads.
# usage: study_command_test.sh <mechgen> <source dir> [<mpiexec> (empty: no MPI)]
set -uo pipefail
mechgen=$(realpath "$1") source_dir=$(realpath "$2") mpiexec=${3:-}
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
cd "$root" || exit 1
export MECHGEN_CACHE_DIR=$root/cache
cp "$source_dir/models/fourbar.yaml" fourbar.yaml
cp "$source_dir/models/fourbar.study.yaml" study.yaml
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { echo "ok $*"; }

"$mechgen" study --verbose fourbar.yaml --study study.yaml --threads 1 --csv one.csv --tolerance-csv tol.csv \
  --envelope-csv env.csv --summary-csv sum_one.csv --histogram-csv hist_one.csv > one.out 2> one.err
status=$?
[ "$status" -eq 0 ] || fail "1 thread: exit status $status: $(cat one.err)"
"$mechgen" study --verbose fourbar.yaml --study study.yaml --threads 2 --csv two.csv --tolerance-csv tol_two.csv \
  --envelope-csv env_two.csv --summary-csv sum_two.csv --histogram-csv hist_two.csv --quiet > two.out 2> two.err
status=$?
[ "$status" -eq 0 ] || fail "2 threads: exit status $status: $(cat two.err)"
grep -q "compiling" two.err && fail "the second run compiled again"
if cmp -s one.csv two.csv; then ok "1 and 2 threads: the same bytes"; else fail "1 and 2 threads differ"; fi
# The design study (tolerance: true, the envelope of coupler.P, design_margin) through the model
# view: its samples' CSV, tolerance CSV, envelope CSV, summary and histograms the per-model
# program's (MECHGEN_VIEW=0, compiled here once for the test, with MPI where CMake found it)
# byte for byte, at 1 and 2 threads.
for t in one two; do
  MECHGEN_VIEW=0 "$mechgen" study fourbar.yaml --study study.yaml --threads $([ $t = one ] && echo 1 || echo 2) \
    --csv p_$t.csv --tolerance-csv p_tol_$t.csv --envelope-csv p_env_$t.csv --summary-csv p_sum_$t.csv \
    --histogram-csv p_hist_$t.csv --quiet > p_$t.out 2> p_$t.err ||
    fail "MECHGEN_VIEW=0, $t: exit status $?: $(cat p_$t.err)"
  grep -q "mechgen_view --name .* study " $t.err && ! grep -q "not through the model view" $t.err ||
    fail "the design study, $t thread(s): not through the model view: $(cat $t.err)"
  [ $t = one ] && v=tol.csv w=env.csv || v=tol_two.csv w=env_two.csv
  if [ -s p_$t.csv ] && cmp -s $t.csv p_$t.csv && cmp -s $v p_tol_$t.csv && cmp -s $w p_env_$t.csv &&
     cmp -s sum_$t.csv p_sum_$t.csv && cmp -s hist_$t.csv p_hist_$t.csv; then
    ok "the design study, $t thread(s): the view's CSV, tolerance and envelope CSVs, summary and histograms" \
       "are the per-model program's bytes"
  else fail "the design study, $t thread(s): the view's outputs differ from the per-model program's"; fi
done
"$mechgen" study fourbar.yaml --study study.yaml --threads 3 --csv three.csv --tolerance-csv tol3.csv \
  --envelope-csv env3.csv --quiet > three.out 2> three.err || fail "3 threads: exit status $?: $(cat three.err)"
if cmp -s one.csv three.csv && cmp -s tol.csv tol3.csv && cmp -s env.csv env3.csv; then
  ok "3 threads: the same bytes (samples, tolerance, envelope)"; else fail "3 threads differ"; fi
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

grep -q "compiling .* with MPI" p_one.err && compiled_mpi=1 || compiled_mpi=0

# analysis: positions (the coupler point at listed inputs, no velocities: the cheapest analysis):
# 1 and 2 threads the same bytes, one row per sample, the analysis named in the first line.
cat > pos.yaml << 'EOF'
method: monte_carlo
count: 20000
seed: 7
analysis: positions
at: [0, 60deg, 120deg]
parameters:
  a: {tolerance: 0.01}
  b: {tolerance: 0.01}
  xi: {tolerance: 0.01}
metrics:
  - {kind: at, column: coupler.P.x, step: 1}
  - {kind: max, column: coupler.P.y}
  - {kind: path_deviation, point: coupler.P}
histogram_bins: 16
EOF
for t in 1 2 3; do
  "$mechgen" study fourbar.yaml --study pos.yaml --threads $t --csv pos$t.csv --summary-csv possum$t.csv \
    --histogram-csv poshist$t.csv --quiet > pos$t.out 2> pos$t.err ||
    fail "positions, $t thread(s): exit status $?: $(cat pos$t.err)"
done
if cmp -s pos1.csv pos2.csv && cmp -s pos1.csv pos3.csv; then ok "positions: 1, 2 and 3 threads the same bytes"
else fail "positions: 1, 2 and 3 threads differ"; fi
# Statistics alone (rows: none, issue 45): no row per sample; the summary and the histograms at
# 1, 2 and 3 threads the same bytes, and the same as the run with rows (but the first line,
# which names the study file); --csv refused (exit 2, one line, nothing written).
{ echo "rows: none"; cat pos.yaml; } > stats.yaml
for t in 1 2 3; do
  "$mechgen" study fourbar.yaml --study stats.yaml --threads $t --summary-csv sum$t.csv --histogram-csv hist$t.csv \
    --quiet > stats$t.out 2> stats$t.err || fail "rows: none, $t thread(s): exit status $?: $(cat stats$t.err)"
done
if cmp -s sum1.csv sum2.csv && cmp -s sum1.csv sum3.csv && cmp -s hist1.csv hist2.csv && cmp -s hist1.csv hist3.csv
then ok "rows: none: 1, 2 and 3 threads the same bytes"; else fail "rows: none: 1, 2 and 3 threads differ"; fi
if cmp -s <(tail -n +2 sum1.csv) <(tail -n +2 possum1.csv) && cmp -s <(tail -n +2 hist1.csv) <(tail -n +2 poshist1.csv) &&
   cmp -s possum1.csv possum3.csv; then ok "rows: none: the statistics of the run with rows"
else fail "rows: none: not the statistics of the run with rows"; fi
"$mechgen" study fourbar.yaml --study stats.yaml --csv statsrows.csv > stats.out 2> stats.err
status=$?
[ "$status" -eq 2 ] || fail "rows: none with --csv: exit status $status"
[ "$(grep -c '' stats.err)" -eq 1 ] && grep -q "stats.yaml:1:7" stats.err || fail "rows: none with --csv: $(cat stats.err)"
[ -e statsrows.csv ] && fail "rows: none with --csv: a CSV was written"
# The statistics recomputed from the rows of pos1.csv (the ok samples' finite values of each
# metric): n, min, max and the quantiles (the ceil(p n)-th of sort -g) as the same strings,
# the histogram's counts exactly (the bin of v: floor((v - min) / ((max - min) / 16)), the
# last including max), the mean within 1e-12 and sigma within 1e-9 relative (awk's sums).
header=$(grep -v '^#' pos1.csv | head -1)
for j in 5 6 7; do
  name=$(echo "$header" | cut -d, -f$j)
  grep -v '^#' pos1.csv | tail -n +2 | awk -F, -v j=$j '$NF == "ok" && $j ~ /^-?[0-9]/ { print $j }' | sort -g > col.txt
  line=$(grep "^$name," sum1.csv)
  n=$(grep -c '' col.txt)
  [ "$(echo "$line" | cut -d, -f3)" = "$n" ] || fail "$name: n $(echo "$line" | cut -d, -f3), the rows have $n"
  [ "$(echo "$line" | cut -d, -f6)" = "$(head -1 col.txt)" ] || fail "$name: min $(echo "$line" | cut -d, -f6)"
  [ "$(echo "$line" | cut -d, -f14)" = "$(tail -1 col.txt)" ] || fail "$name: max $(echo "$line" | cut -d, -f14)"
  f=7
  for p in 0.01 0.05 0.25 0.5 0.75 0.95 0.99; do
    rank=$(awk -v p=$p -v n="$n" 'BEGIN { r = p * n; k = int(r); if (k < r) k++; if (k < 1) k = 1; print k }')
    [ "$(echo "$line" | cut -d, -f$f)" = "$(sed -n "${rank}p" col.txt)" ] ||
      fail "$name: quantile $p: $(echo "$line" | cut -d, -f$f), the rows' $rank-th: $(sed -n "${rank}p" col.txt)"
    f=$((f + 1))
  done
  awk -v mean="$(echo "$line" | cut -d, -f4)" -v sigma="$(echo "$line" | cut -d, -f5)" '
    { x[NR] = $1; s += $1 } END { m = s / NR; for (i = 1; i <= NR; ++i) q += (x[i] - m) ^ 2; sd = sqrt(q / (NR - 1))
      dm = (m - mean) / m; ds = (sd - sigma) / sd; exit !(dm < 1e-12 && dm > -1e-12 && ds < 1e-9 && ds > -1e-9) }' col.txt ||
    fail "$name: mean or sigma not those of the rows: $line"
  lo=$(head -1 col.txt) hi=$(tail -1 col.txt)
  awk -v lo="$lo" -v hi="$hi" '{ w = (hi - lo) / 16; b = w > 0 ? int(($1 - lo) / w) : 0; if (b > 15) b = 15; c[b]++ }
    END { for (b = 0; b < 16; ++b) print b "," c[b] + 0 }' col.txt > mine.txt
  grep "^$name," hist1.csv | awk -F, '{ print $2 "," $5 }' > theirs.txt
  cmp -s mine.txt theirs.txt || fail "$name: histogram: $(paste -d' ' mine.txt theirs.txt | tr '\n' ' ')"
done
ok "rows: none: the statistics recomputed from the rows"
# With failing samples (c across the Grashof limit: rows fail at a dead point): the statistics
# are the ok samples' (n = the ok rows, the mean theirs), and rows: none gives them at 3 threads
# as the run with rows at 1 (exit 3: some samples failed).
cat > fail.yaml << 'EOF'
method: monte_carlo
count: 600
seed: 5
steps: 36
parameters:
  a: {tolerance: 0.01}
  c: {distribution: uniform, tolerance: 1.8}
metrics:
  - {kind: max, column: coupler.P.y}
  - {kind: min_transmission_angle}
EOF
{ echo "rows: none"; cat fail.yaml; } > failnone.yaml
"$mechgen" study fourbar.yaml --study fail.yaml --threads 1 --csv fail.csv --summary-csv failsum1.csv --quiet > /dev/null 2>&1
status=$?
"$mechgen" study fourbar.yaml --study failnone.yaml --threads 3 --summary-csv failsum3.csv --quiet > /dev/null 2>&1
status3=$?
[ "$status" -eq 3 ] && [ "$status3" -eq 3 ] || fail "failing samples: exit status $status and $status3, not 3"
cmp -s <(tail -n +2 failsum1.csv) <(tail -n +2 failsum3.csv) || fail "failing samples: rows: none at 3 threads differs"
grep -v '^#' fail.csv | tail -n +2 | awk -F, '$NF == "ok" { n++; s += $4 } END { printf "%d %.17g\n", n, s / n }' > okrows.txt
read -r okn okmean < okrows.txt
line=$(grep '^max_coupler.P.y,' failsum1.csv)
if [ "$okn" -gt 0 ] && [ "$okn" -lt 600 ] && [ "$(echo "$line" | cut -d, -f3)" = "$okn" ] &&
   awk -v a="$okmean" -v b="$(echo "$line" | cut -d, -f4)" 'BEGIN { d = (a - b) / b; exit !(d < 1e-12 && d > -1e-12) }'
then ok "failing samples: the statistics of the $okn ok samples of 600"
else fail "failing samples: $okn ok rows (mean $okmean), the summary: $line"; fi
[ "$(grep -v '^#' pos1.csv | tail -n +2 | wc -l)" -eq 20000 ] || fail "positions: not 20000 rows"
head -1 pos1.csv | grep -q "analysis positions in 2 steps" || fail "positions: $(head -1 pos1.csv)"

# `mechgen study STUDY.yaml`: the study names its model, relative to itself.
mkdir -p sub
sed 's|^method: monte_carlo|model: ../fourbar.yaml\nmethod: monte_carlo|' study.yaml > sub/named.yaml
"$mechgen" study sub/named.yaml --threads 4 --csv named.csv --quiet > named.out 2> named.err
status=$?
[ "$status" -eq 0 ] || fail "study-file form: exit status $status: $(cat named.err)"
grep -q "compiling" named.err && fail "the study-file form compiled again"
# The same bytes but the first line, which names the study file.
if cmp -s <(tail -n +2 one.csv) <(tail -n +2 named.csv); then ok "mechgen study STUDY.yaml, 4 threads: the same bytes"
else fail "the study-file form or 4 threads differ"; fi
head -1 named.csv | grep -q "^# mechgen study, model fourbar: sub/named.yaml, " || fail "named: $(head -1 named.csv)"
sed 's|^method: monte_carlo|method: monte_carlo|' study.yaml > sub/unnamed.yaml
"$mechgen" study sub/unnamed.yaml --csv unnamed.csv > unnamed.out 2> unnamed.err
status=$?
[ "$status" -eq 2 ] || fail "a study without model: run alone: exit status $status"
grep -Eq "^sub/unnamed.yaml:[0-9]+:1: error: a study run as .mechgen study sub/unnamed.yaml. names its model" unnamed.err ||
  fail "a study without model: $(cat unnamed.err)"

# Resuming: stopped after 500 samples (whole chunks: 512), no CSV yet, the shards kept; run
# again (1 thread): the same bytes, the shards removed.
"$mechgen" study fourbar.yaml --study study.yaml --threads 2 --csv resumed.csv --stop-after 500 --quiet > stop.out 2> stop.err
status=$?
[ "$status" -eq 4 ] || fail "--stop-after: exit status $status: $(cat stop.err)"
[ -e resumed.csv ] && fail "--stop-after: a CSV was written"
[ "$(ls resumed.csv.shards | grep -c '^chunk-')" -eq 8 ] || fail "--stop-after 500: not 8 shards of 64: $(ls resumed.csv.shards)"
"$mechgen" study fourbar.yaml --study study.yaml --threads 1 --csv resumed.csv --quiet > resume.out 2> resume.err
status=$?
[ "$status" -eq 0 ] || fail "resume: exit status $status: $(cat resume.err)"
grep -q "^resumed: 512 samples from the shards in resumed.csv.shards; 24 of 32 chunks left" resume.out ||
  fail "resume: $(cat resume.out)"
if cmp -s one.csv resumed.csv; then ok "stopped and resumed: the same bytes"; else fail "stopped and resumed: differ"; fi
[ -e resumed.csv.shards ] && fail "the shards were not removed after the study"
# Shards of another study are left alone: exit 1.
mkdir -p other.csv.shards && echo "mechgen study shards 1" > other.csv.shards/study.key
"$mechgen" study fourbar.yaml --study study.yaml --csv other.csv > other.out 2> other.err
status=$?
[ "$status" -eq 1 ] || fail "another study's shards: exit status $status"
grep -q "holds the shards of another study" other.err || fail "another study's shards: $(cat other.err)"
# Killed (SIGKILL) once a few shards are written, run again: the same bytes as a run that was not.
sed 's/^count: 2000/count: 12000/' study.yaml > big.yaml
"$mechgen" study fourbar.yaml --study big.yaml --threads 2 --csv big_whole.csv --quiet > /dev/null 2>&1 ||
  fail "the larger study: exit status $?"
"$mechgen" study fourbar.yaml --study big.yaml --threads 1 --csv big.csv --quiet > /dev/null 2>&1 &
pid=$!
for _ in $(seq 1 400); do
  [ "$(ls big.csv.shards 2> /dev/null | grep -c '^chunk-')" -ge 3 ] && break
  sleep 0.02
done
kill -KILL "$pid" 2> /dev/null
wait "$pid" 2> /dev/null
killed=$(ls big.csv.shards 2> /dev/null | grep -c '^chunk-')
[ -e big.csv ] && fail "killed: a CSV was written (the study ended before the kill)"
"$mechgen" study fourbar.yaml --study big.yaml --threads 2 --csv big.csv --quiet > big.out 2> big.err ||
  fail "killed and resumed: exit status $?: $(cat big.err)"
grep -q "^resumed: " big.out || fail "killed ($killed shards): nothing resumed: $(head -3 big.out)"
if cmp -s big_whole.csv big.csv; then ok "killed after $killed shards and resumed: the same bytes"; else fail "killed and resumed: differ"; fi

# MPI: two ranks (one thread each) and one rank give the bytes of the serial run; a two-rank run
# stopped part way resumes serially to the same bytes.
if [ -z "$mpiexec" ]; then
  echo "SKIP: MPI: CMake found no MPI C++ compiler (install libopenmpi-dev openmpi-bin: scripts/deps.sh)"
elif [ "$compiled_mpi" -ne 1 ]; then
  fail "MPI: CMake found MPI but mechgen compiled the study without it: $(cat p_one.err)"
else
  [ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  for np in 2 1; do
    "$mpiexec" --oversubscribe -np $np "$mechgen" study fourbar.yaml --study study.yaml --threads 1 --csv mpi$np.csv \
      --quiet > mpi$np.out 2> mpi$np.err
    status=$?
    [ "$status" -eq 0 ] || fail "mpirun -np $np: exit status $status: $(tail -5 mpi$np.err)"
    if cmp -s one.csv mpi$np.csv; then ok "mpirun -np $np: the same bytes"; else fail "mpirun -np $np: differ"; fi
  done
  grep -q "on each of 2 ranks" mpi2.out || fail "mpirun -np 2: not two ranks: $(head -1 mpi2.out)"
  "$mpiexec" --oversubscribe -np 2 "$mechgen" study fourbar.yaml --study study.yaml --threads 1 --csv mpir.csv \
    --stop-after 700 --quiet > mpir.out 2> mpir.err
  status=$?
  [ "$status" -eq 4 ] || fail "mpirun -np 2 --stop-after: exit status $status: $(tail -5 mpir.err)"
  "$mechgen" study fourbar.yaml --study study.yaml --threads 2 --csv mpir.csv --quiet > mpir2.out 2> mpir2.err
  grep -q "^resumed: 704 samples" mpir2.out || fail "resumed after two ranks: $(head -3 mpir2.out)"
  if cmp -s one.csv mpir.csv; then ok "two ranks stopped, resumed serially: the same bytes"; else fail "two ranks stopped and resumed: differ"; fi
fi

# Through the model view (issue 43): `mechgen study` runs the study on the runtime compiled once
# (mechgen_view study on the model's shared object) and builds the per-model study program only
# for what the view does not do yet. The CSV, the summary and the histograms through the view
# are the per-model program's (MECHGEN_VIEW=0) byte for byte, at 1 and 2 threads: the design
# study above, the kinematic sweep and the positions of the four-bar, the statics and the free simulation (with the
# kinetostatics' reactions) of the massive four-bar (one more per-model compile, ~60 s), the
# free simulation with Coulomb friction (stick and slip, a push that breaks the block away) of
# tests/dynamics' block on an incline (one more, ~40 s), the engine's cycle of engine_single
# (analysis: engine) and the punch press's flywheel cycle with its located switches and a derived
# parameter (analysis: flywheel; two more, ~80 s each), the driven simulation (drive:,
# dynamics/prescribed.h) of the massive four-bar's crank (a rest-to-rest move, the actuator torque
# and the bearings) and of the incline's block driven up the slope (its Coulomb friction in
# lambda); --verbose says which ran. A new model's first study compiles its object alone.
# tolerance: true of a flywheel study (the first order of the cycle's metrics from the view's
# cycle design derivatives, machines/view_machines.h) on tests/design's press (every parameter
# a design parameter): the samples', tolerance and summary CSVs the per-model program's bytes
# at 1 and 2 threads, with a first order (a positive fo_sigma) for each of the
# four cycle metrics.
# A run under an MPI launcher (the ranks) goes through the view too: nothing a study asks is
# refused by mechgen_view built with MPI.
grep -v '^tolerance:\|^envelope:\|^clearance:\|^  B: {parameter\|design_margin' study.yaml > view_sweep.yaml
cp "$source_dir/models/fourbar_massive.yaml" "$source_dir/models/engine_single.yaml" \
   "$source_dir/tests/flywheel/models/punch_press.yaml" .
cat > view_engine.yaml << 'EOF'
method: grid
analysis: engine
rpm: 3000
steps: 360
gas: {heat: 800, burn_start: -15deg}
parameters:
  r: {values: [0.040, 0.043]}
  m_pis: {values: [0.4, 0.5]}
metrics:
  - {kind: mean_torque}
  - {kind: peak_torque}
  - {kind: energy_fluctuation}
  - {kind: flywheel_inertia, C_s: 0.02}
  - {kind: speed_fluctuation}
  - {kind: failures}
EOF
cat > view_flywheel.yaml << 'EOF'
method: lhs
count: 12
seed: 5
analysis: flywheel
omega: 31.41592653589793
steps: 720
parameters:
  delta: {tolerance: 0.001}
  F0: {tolerance: 2000}
  m3: {tolerance: 0.5}
metrics:
  - {kind: mean_torque}
  - {kind: peak_torque}
  - {kind: energy_fluctuation}
  - {kind: flywheel_inertia, C_s: 0.05}
  - {kind: failures}
EOF
cat > view_statics.yaml << 'EOF'
method: lhs
count: 300
seed: 3
analysis: statics
steps: 36
parameters:
  a: {tolerance: 0.02}
  rho: {tolerance: 0.2}
metrics:
  - {kind: peak_drive}
  - {kind: peak_bearing}
  - {kind: rms, column: coupler.C.y}
  - {kind: max, column: drive_theta_crank}
  - {kind: failures}
EOF
cat > view_simulate.yaml << 'EOF'
method: monte_carlo
count: 60
seed: 2
analysis: simulate
t_end: 1.5
steps: 30
parameters:
  a: {tolerance: 0.01}
  rho: {tolerance: 0.1}
metrics:
  - {kind: max, column: theta_crank}
  - {kind: peak_bearing}
  - {kind: at, column: theta_crank_dot, step: 10}
  - {kind: failures}
EOF
cp "$source_dir/tests/dynamics/models/incline_friction.yaml" .
cat > view_friction.yaml << 'EOF'
method: monte_carlo
count: 40
seed: 4
analysis: simulate
t_end: 2
steps: 40
qd0: [2]
parameters:
  mu: {distribution: uniform, nominal: 0.55, tolerance: 0.1}
  F0: {distribution: uniform, nominal: 20, tolerance: 10}
metrics:
  - {kind: max, column: s_slide}
  - {kind: at, column: s_slide_dot, step: 20}
  - {kind: max, column: friction_slide}
  - {kind: rms, column: stuck}
  - {kind: failures}
EOF
cat > view_drive.yaml << 'EOF'
method: monte_carlo
count: 30
seed: 6
analysis: simulate
t_end: 0.6
steps: 30
drive: {theta_crank: {move: [3.5, 0.05, 0.5]}}
parameters:
  a: {tolerance: 0.01}
  rho: {tolerance: 0.1}
metrics:
  - {kind: peak_drive}
  - {kind: peak_bearing}
  - {kind: at, column: lambda_theta_crank, step: 10}
  - {kind: max, column: balance}
  - {kind: min, column: Q_theta_crank}
  - {kind: failures}
EOF
cat > view_drive_friction.yaml << 'EOF'
method: monte_carlo
count: 20
seed: 7
analysis: simulate
t_end: 1
steps: 20
drive: {s_slide: {speed: 1}}
parameters:
  mu: {distribution: uniform, nominal: 0.4, tolerance: 0.2}
metrics:
  - {kind: peak_drive}
  - {kind: at, column: lambda_s_slide, step: 10}
  - {kind: max, column: W_act}
  - {kind: failures}
EOF
"$mechgen" study --verbose fourbar_massive.yaml --study view_statics.yaml --quiet > vfirst.out 2> vfirst.err ||
  fail "view, a new model: exit status $?: $(cat vfirst.err)"
grep -q "the runtime is compiled once" vfirst.err && ! grep -q "compiling the study command" vfirst.err ||
  fail "view, a new model: not the model's object alone: $(cat vfirst.err)"
for case in "fourbar.yaml view_sweep" "fourbar.yaml pos" "fourbar_massive.yaml view_statics" \
            "fourbar_massive.yaml view_simulate" "incline_friction.yaml view_friction" \
            "engine_single.yaml view_engine" "punch_press.yaml view_flywheel" "fourbar_massive.yaml view_drive" \
            "incline_friction.yaml view_drive_friction"; do
  set -- $case
  for t in 1 2; do
    "$mechgen" study --verbose "$1" --study "$2.yaml" --threads $t --csv "$2_v$t.csv" --summary-csv "$2_vs$t.csv" \
      --histogram-csv "$2_vh$t.csv" --quiet > "$2_v$t.out" 2> "$2_v$t.err"
    status=$?
    MECHGEN_VIEW=0 "$mechgen" study "$1" --study "$2.yaml" --threads $t --csv "$2_p$t.csv" --summary-csv "$2_ps$t.csv" \
      --histogram-csv "$2_ph$t.csv" --quiet > "$2_p$t.out" 2> "$2_p$t.err"
    pstatus=$?
    [ "$status" -eq 0 ] && [ "$pstatus" -eq 0 ] ||
      fail "$2, $t thread(s): exit status $status (view), $pstatus: $(cat "$2_v$t.err" "$2_p$t.err")"
    grep -q "mechgen_view --name .* study " "$2_v$t.err" && ! grep -q "not through the model view" "$2_v$t.err" ||
      fail "$2, $t thread(s): not through the model view: $(cat "$2_v$t.err")"
    if [ "$(grep -vc '^#' "$2_v$t.csv")" -gt 1 ] && cmp -s "$2_v$t.csv" "$2_p$t.csv" &&
       cmp -s "$2_vs$t.csv" "$2_ps$t.csv" && cmp -s "$2_vh$t.csv" "$2_ph$t.csv"; then
      ok "$2, $t thread(s): the model view's CSV, summary and histograms are the per-model program's bytes"
    else fail "$2, $t thread(s): the model view's outputs differ from the per-model program's"; fi
  done
done
cp "$source_dir/tests/design/models/design_press.yaml" .
cat > flytol.yaml << 'EOF'
method: monte_carlo
count: 12
seed: 5
analysis: flywheel
omega: 6.283185307179586
steps: 360
tolerance: true
parameters:
  a: {tolerance: 0.002}
  m3: {tolerance: 0.5}
  c: {tolerance: 20}
metrics:
  - {kind: mean_torque}
  - {kind: peak_torque}
  - {kind: energy_fluctuation}
  - {kind: flywheel_inertia, C_s: 0.05}
  - {kind: failures}
EOF
for t in 1 2; do
  "$mechgen" study --verbose design_press.yaml --study flytol.yaml --threads $t --csv flytol_v$t.csv \
    --tolerance-csv flytol_vt$t.csv --summary-csv flytol_vs$t.csv --quiet > flytol_v$t.out 2> flytol_v$t.err
  status=$?
  MECHGEN_VIEW=0 "$mechgen" study design_press.yaml --study flytol.yaml --threads $t --csv flytol_p$t.csv \
    --tolerance-csv flytol_pt$t.csv --summary-csv flytol_ps$t.csv --quiet > flytol_p$t.out 2> flytol_p$t.err
  pstatus=$?
  [ "$status" -eq 0 ] && [ "$pstatus" -eq 0 ] ||
    fail "flytol, $t thread(s): exit status $status (view), $pstatus: $(cat flytol_v$t.err flytol_p$t.err)"
  grep -q "mechgen_view --name .* study " flytol_v$t.err && ! grep -q "not through the model view" flytol_v$t.err ||
    fail "flytol, $t thread(s): not through the model view: $(cat flytol_v$t.err)"
  [ "$(grep -v '^#' flytol_vt$t.csv | awk -F, '$1 ~ /torque|energy|flywheel/ && $4 ~ /^[0-9]/ && $4 + 0 > 0' | grep -c '')" -eq 4 ] ||
    fail "flytol, $t thread(s): not a first order for each cycle metric: $(grep -v '^#' flytol_vt$t.csv)"
  if cmp -s flytol_v$t.csv flytol_p$t.csv && cmp -s flytol_vt$t.csv flytol_pt$t.csv &&
     cmp -s flytol_vs$t.csv flytol_ps$t.csv; then
    ok "flytol (tolerance: true of a flywheel study), $t thread(s): the model view's CSVs are the per-model program's bytes"
  else fail "flytol, $t thread(s): the model view's outputs differ from the per-model program's"; fi
done
# Under an MPI launcher the ranks run through the model view (mechgen_view is built with the MPI
# CMake found, runtime/CMakeLists.txt): no per-model program, two ranks, the bytes of the view's
# serial run.
if [ -n "$mpiexec" ] && [ "$compiled_mpi" -eq 1 ]; then
  "$mpiexec" --oversubscribe -np 2 "$mechgen" study --verbose fourbar.yaml --study view_sweep.yaml --threads 1 \
    --csv vmpi.csv --quiet > vmpi.out 2> vmpi.err || fail "view_sweep under mpirun -np 2: exit status $?: $(tail -5 vmpi.err)"
  [ "$(grep -c "mechgen_view --name .* study " vmpi.err)" -eq 2 ] && ! grep -q "not through the model view" vmpi.err &&
    grep -q "on each of 2 ranks" vmpi.out || fail "view_sweep under mpirun -np 2: not two ranks through the model view: $(cat vmpi.err)"
  cmp -s vmpi.csv view_sweep_v1.csv || fail "view_sweep under mpirun -np 2: not the bytes of the view's serial run"
fi
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
# The resume options refuse what cannot mean anything: exit 2, one line, nothing written.
for bad in "--stop-after 0" "--stop-after -3" "--stop-after nan" "--stop-after 1e300" "--chunk 0" "--chunk -1" \
           "--chunk inf"; do
  # shellcheck disable=SC2086
  "$mechgen" study fourbar.yaml --study study.yaml --csv badopt.csv --quiet $bad > opt.out 2> opt.err
  status=$?
  [ "$status" -eq 2 ] || fail "$bad: exit status $status"
  [ "$(grep -c '' opt.err)" -eq 1 ] || fail "$bad: not one line: $(cat opt.err)"
  [ -e badopt.csv ] && fail "$bad: a CSV was written"
done

# Hostile study files and options (issue 45): exit 2, one line, nothing written.
mkdir -p dir.yaml
cat > grid.yaml << 'EOF'
method: grid
parameters:
  a: {range: [0.9, 1.1], count: 65536}
  b: {range: [3.4, 3.6], count: 65536}
  c: {range: [2.9, 3.1], count: 65536}
  d: {range: [3.9, 4.1], count: 65536}
metrics: [{kind: failures}]
EOF
sed 's/^  - {kind: failures}$/  - {kind: failures, name: "a,b"}/' study.yaml > comma.yaml
printf 'count: 20\n' | cat study.yaml - > twice.yaml
for bad in "--study dir.yaml" "--study grid.yaml" "--study comma.yaml" "--study twice.yaml" \
           "--study study.yaml --set zz=1" "--study study.yaml --set a=nan" "--study study.yaml --params none.txt"; do
  # shellcheck disable=SC2086
  "$mechgen" study fourbar.yaml $bad --csv hostile.csv --quiet > hostile.out 2> hostile.err
  status=$?
  [ "$status" -eq 2 ] || fail "$bad: exit status $status: $(cat hostile.err)"
  [ "$(grep -c '' hostile.err)" -eq 1 ] || fail "$bad: not one line: $(cat hostile.err)"
  [ -e hostile.csv ] && fail "$bad: a CSV was written"
done
"$mechgen" study fourbar.yaml --study grid.yaml > hostile.out 2> hostile.err
grep -q "^grid.yaml:4:3: error: a grid of 65536 x 65536 x ... values is more than 100000000 samples" hostile.err ||
  fail "grid: $(cat hostile.err)"
"$mechgen" study fourbar.yaml --study dir.yaml > hostile.out 2> hostile.err
grep -q "^dir.yaml: error: is a directory" hostile.err || fail "directory: $(cat hostile.err)"
# --params then --set, before the study: a parameter without nominal: is drawn about the value
# set (the CSV's mean of a over 2000 samples, sigma 0.01/3: within 0.001 of 1.05), the header
# says what was set.
printf 'a = 1.02\nb = 3.55\n' > base.txt
"$mechgen" study fourbar.yaml --study study.yaml --params base.txt --set a=1.05 --csv set.csv --quiet > set.out 2> set.err ||
  fail "--set: exit status $?: $(cat set.err)"
grep -q "^the model's parameters set by --params/--set: a = 1.05 (default 1), b = 3.55 (default 3.5)" set.out ||
  fail "--set: $(head -3 set.out)"
head -1 set.csv | grep -q "set by --params/--set: a = 1.05 (default 1), b = 3.55 (default 3.5)" ||
  fail "--set: CSV header $(head -1 set.csv)"
grep -v '^#' set.csv | awk -F, 'NR > 1 { s += $2; n++ } END { m = s / n; exit !(m > 1.049 && m < 1.051) }' ||
  fail "--set a=1.05: the samples of a are not about 1.05"

# A study of 10^8 samples (the most) stopped after one chunk (issue 45, #5): run end to end in
# chunks, it holds that chunk alone (under a 2 GB address-space limit; drawing every sample and
# result first took ~8 GB and aborted with bad_alloc), exit 4, one shard; resumed, the next.
cat > huge.yaml << 'EOF'
method: monte_carlo
count: 100000000
seed: 3
analysis: positions
at: [0, 60deg]
parameters:
  a: {tolerance: 0.01}
  b: {tolerance: 0.01}
  c: {tolerance: 0.01}
metrics:
  - {kind: at, column: coupler.P.x, step: 1}
EOF
for run in 1 2; do
  (ulimit -v 2000000; "$mechgen" study fourbar.yaml --study huge.yaml --threads 2 --quiet --stop-after 64 \
    --shards huge.shards > huge.out 2> huge.err)
  status=$?
  [ "$status" -eq 4 ] || fail "10^8 samples, --stop-after 64 (run $run): exit status $status: $(tail -3 huge.err)"
  [ "$(ls huge.shards 2> /dev/null | grep -c '^chunk-')" -eq "$run" ] ||
    fail "10^8 samples (run $run): not $run shard(s): $(ls huge.shards)"
done
grep -q "^resumed: 65536 samples from the shards in huge.shards; 1525 of 1526 chunks left" huge.out ||
  fail "10^8 samples, resumed: $(cat huge.out)"

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
