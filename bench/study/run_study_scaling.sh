#!/usr/bin/env bash
# Scaling of `mechgen study` (docs/studies.md "Speed"): the same study on 1 and 2 threads and
# under `mpirun --oversubscribe -np R` (R = 1, 2, 4, 8; one thread per rank), the whole
# command's wall time (mpirun's start of the ranks included) and rank 0's own account (its
# part, the wait for the slowest rank, the gather), for a four-bar sweep of 360 steps and a
# positions-only Monte-Carlo of 10^6 coupler points. Shards off (--no-shards): their fsyncs are
# not what is measured. Prints the load average before and after: on a shared machine compare
# ratios, not absolute times.
# usage: bench/study/run_study_scaling.sh <mechgen> <source dir> [mpiexec (default: mpirun)] [runs (3)]
set -uo pipefail
mechgen=$(realpath "$1") source_dir=$(realpath "$2") mpiexec=${3:-mpirun} runs=${4:-3}
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
cd "$root" || exit 1
export MECHGEN_CACHE_DIR=${MECHGEN_CACHE_DIR:-$root/cache}
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cp "$source_dir/models/fourbar.yaml" fourbar.yaml
cat > sweep.yaml << 'Y'
method: monte_carlo
count: 4000
steps: 360
parameters:
  a: {tolerance: 0.01}
  b: {tolerance: 0.01}
  c: {tolerance: 0.01}
  d: {tolerance: 0.01}
metrics:
  - {kind: max, column: coupler.P.y}
  - {kind: min_transmission_angle}
  - {kind: path_deviation, point: coupler.P}
Y
cat > positions.yaml << 'Y'
method: monte_carlo
count: 1000000
analysis: positions
at: [60deg]
parameters:
  a: {tolerance: 0.01}
  b: {tolerance: 0.01}
  c: {tolerance: 0.01}
  d: {tolerance: 0.01}
  xi: {tolerance: 0.01}
  eta: {tolerance: 0.01}
metrics:
  - {kind: at, column: coupler.P.x, step: 0}
  - {kind: at, column: coupler.P.y, step: 0}
Y
"$mechgen" study fourbar.yaml --study sweep.yaml --help > /dev/null 2>&1  # compile the driver once
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
median() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
run() {  # label, command...: the median wall time of $runs runs, and rank 0's last account
  local label=$1; shift
  local times=()
  for _ in $(seq 1 "$runs"); do
    local t0 t1
    t0=$(date +%s.%N)
    "$@" > out.txt 2> err.txt || { echo "$label: failed: $(tail -2 err.txt)"; return; }
    t1=$(date +%s.%N)
    times+=("$(echo "$t1 - $t0" | bc)")
  done
  printf '%-28s wall %6.2f s (median of %d)  %s\n' "$label" "$(printf '%s\n' "${times[@]}" | median)" "$runs" \
    "$(grep -o 'rank 0 ran.*' out.txt)"
}
for study in sweep positions; do
  for t in 1 2; do
    run "$study --threads $t" "$mechgen" study fourbar.yaml --study $study.yaml --threads $t --csv $study.csv --no-shards --quiet
  done
  cp $study.csv $study.serial.csv
  for np in 1 2 4 8; do
    run "$study mpirun -np $np" "$mpiexec" --oversubscribe -np $np "$mechgen" study fourbar.yaml --study $study.yaml \
      --threads 1 --csv $study.csv --no-shards --quiet
    cmp -s $study.csv $study.serial.csv || echo "$study mpirun -np $np: NOT the serial bytes"
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
