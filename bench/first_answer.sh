#!/usr/bin/env bash
# The first answer of `mechgen <command> MODEL` on models never seen before (issue 43's
# targets), beside the per-model program's (MECHGEN_VIEW=0) and the model kernel's own compile.
#
# usage: bench/first_answer.sh [build dir (default build)] [model:command ... (default:
#        fourbar:sweep slider_crank_friction:statics slider_crank_motor:simulate watt_sixbar:sweep
#        engine_single:engine tests/flywheel/models/punch_press:flywheel fourbar:study)]
# A model is a file of models/ by its name, or a path from the source tree without .yaml.
#
# Each model file is copied outside the tree under a new name (a model never seen: the name
# goes into the generated code, so no compiler cache can have it; CXX is unset, so no ccache),
# with a fresh cache directory. Measured, wall clock, one run each on whatever the machine is
# doing (say so beside the figures):
#   kernel   g++ -O3 -c <name>.cc of the generated model (the floor of any first answer)
#   first    the first `mechgen <command>` (generation, the model's object, the answer)
#   second   a second command on the same model (a sweep with other options: the object cached)
#   cached   the same command again
#   per-model the first answer with MECHGEN_VIEW=0 (the per-model program)
# Targets: first <= 5 s and <= kernel + 1 s; second <= 1 s; cached <= 0.2 s.
set -uo pipefail
build=$(realpath "${1:-build}")
shift || true
models=("$@")
[[ ${#models[@]} -gt 0 ]] ||
  models=(fourbar:sweep slider_crank_friction:statics slider_crank_motor:simulate watt_sixbar:sweep
          engine_single:engine tests/flywheel/models/punch_press:flywheel fourbar:study)
source_dir=$(cd "$(dirname "$0")/.." && pwd)
mechgen=$build/generator/mechgen
[[ -x $mechgen ]] || { echo "error: no $mechgen: build first"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset CXX
stamp=$(date +%s%N | tail -c 7)
seconds() { python3 -c "import sys; print(f'{(int(sys.argv[2]) - int(sys.argv[1])) / 1e9:.2f}')" "$1" "$2"; }
verdict() { python3 -c "import sys; print('PASS' if float(sys.argv[1]) <= float(sys.argv[2]) else 'MISS')" "$1" "$2"; }
timed() {  # timed <out var> <command...>: the wall time in s; the command's output to $work/last.*
  local var=$1 t0 t1
  shift
  t0=$(date +%s%N)
  "$@" > "$work/last.out" 2> "$work/last.err"
  local status=$?
  t1=$(date +%s%N)
  printf -v "$var" '%s' "$(seconds "$t0" "$t1")"
  if [[ $status -ne 0 ]]; then
    echo "error: $* (exit $status): $(head -5 "$work/last.err")" >&2
    return 1
  fi
}

echo "first answers of mechgen on models never seen before ($(nproc) cores; load $(cut -d' ' -f1-3 /proc/loadavg))"
printf '%-32s %8s %8s %8s %8s %10s   %s\n' "model: command" kernel first second cached per-model "targets: first <= 5 s and <= kernel + 1 s, second <= 1 s, cached <= 0.2 s"
for pair in "${models[@]}"; do
  model=${pair%%:*} command=${pair#*:}
  case $command in
    sweep) options=(--steps 360) ;;
    statics) options=(--steps 360 --dead-zones) ;;
    simulate) options=(--t-end 1 --dt 0.005 --friction off) ;;
    engine) options=(cycle --rpm 3000) ;;
    flywheel) options=(--rpm 60 --cs 0.02) ;;
    # models/fourbar.study.yaml without the design derivatives (tolerance, envelope,
    # design_margin), 200 samples on 2 threads.
    study) options=(--study study.yaml --threads 2) ;;
    *) echo "error: no command $command"; continue ;;
  esac
  file=$source_dir/models/$model.yaml
  [[ $model == */* ]] && file=$source_dir/$model.yaml
  model=$(basename "$model")
  name="fa_${model}_${command}_${stamp}"  # one model per row: a row never finds another's object
  dir=$work/$name
  mkdir -p "$dir"
  sed "s/^name: .*/name: $name/" "$file" > "$dir/$name.yaml"
  cd "$dir" || exit 1
  grep -v -E '^(tolerance|envelope):|design_margin' "$source_dir/models/fourbar.study.yaml" |
    sed 's/^count: .*/count: 200/' > study.yaml
  # The kernel's own compile (the generated model, double only).
  "$mechgen" generate "$name.yaml" --out-dir gen > /dev/null 2>&1 || { echo "error: cannot generate $model"; continue; }
  timed kernel c++ -O3 -std=c++17 -isystem /usr/include/eigen3 -c "gen/$name.cc" -o kernel.o || continue
  export MECHGEN_CACHE_DIR=$dir/cache
  timed first "$mechgen" "$command" "$name.yaml" "${options[@]}" --csv first.csv || continue
  timed second "$mechgen" sweep "$name.yaml" --steps 90 --qd 2 --table 0 --csv second.csv || continue
  timed cached "$mechgen" sweep "$name.yaml" --steps 90 --qd 2 --table 0 --csv cached.csv || continue
  export MECHGEN_CACHE_DIR=$dir/cache_per_model
  timed per_model env MECHGEN_VIEW=0 "$mechgen" "$command" "$name.yaml" "${options[@]}" --csv per_model.csv || continue
  cmp -s first.csv per_model.csv || echo "note: $model $command: the CSVs of the two routes differ"
  limit=$(python3 -c "import sys; print(min(5.0, float(sys.argv[1]) + 1.0))" "$kernel")
  printf '%-32s %8s %8s %8s %8s %10s   first %s, second %s, cached %s\n' "$model: $command" "$kernel" "$first" \
    "$second" "$cached" "$per_model" "$(verdict "$first" "$limit")" "$(verdict "$second" 1)" "$(verdict "$cached" 0.2)"
  cd "$work" || exit 1
done
echo "(seconds, wall clock, one run each; every command through the view but simulate --design)"
