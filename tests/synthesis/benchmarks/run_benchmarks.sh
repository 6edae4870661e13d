#!/usr/bin/env bash
# The five path-synthesis benchmark tasks over seeds 1..N: best, median and worst error (sum of
# squared distances) of the N runs (each the task's own budget, all restarts included), the
# evaluations per run and the CPU time. Not a ctest (minutes); the figures are in
# docs/synthesis.md. usage: run_benchmarks.sh <mechgen> [N=50] [threads=1] [case names, e.g. "case2 case3"]
set -uo pipefail
mechgen=$(realpath "$1") n=${2:-50} threads=${3:-1} cases=${4:-}
here=$(cd "$(dirname "$0")" && pwd)
model=$here/../models/synth_fourbar.yaml
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
printf '%-16s %6s %12s %12s %12s %12s %10s %9s\n' case runs best median worst evaluations cpu_s feasible
for task in "$here"/case*.yaml; do
  name=$(basename "$task" .yaml)
  if [ -n "$cases" ] && ! [[ " $cases " == *" ${name%%_*} "* ]]; then continue; fi
  : > "$out/errors"
  evals=0 cpu=0 feasible=0
  for seed in $(seq 1 "$n"); do
    "$mechgen" synthesize "$model" --task "$task" --seed "$seed" --threads "$threads" --out "$out/r" > "$out/log" 2>&1
    if [ $? = 0 ]; then
      feasible=$((feasible + 1))
      grep '^error (sum' "$out/log" | sed 's/.*: \([^ ]*\) .*/\1/' >> "$out/errors"
    fi
    evals=$(grep '^evaluations:' "$out/log" | awk '{print $2}')
    cpu=$(grep '^evaluations:' "$out/log" | sed 's/.*cpu \([^ ]*\) s.*/\1/' | awk -v c="$cpu" '{print c + $1}')
  done
  sort -g "$out/errors" | awk -v name="$name" -v runs="$n" -v evals="$evals" -v cpu="$cpu" -v feasible="$feasible" '
    { e[NR] = $1 } END { if (NR == 0) { printf "%-16s %6d %12s\n", name, runs, "none"; exit }
      printf "%-16s %6d %12.4g %12.4g %12.4g %12d %10.1f %9d\n", name, runs, e[1], e[int((NR + 1) / 2)], e[NR], evals, cpu / runs, feasible }'
done
