#!/usr/bin/env bash
# The README's first command: install what is missing, build the generator and the
# `fourbar` solver, and run the main job — sweep a full crank turn of models/fourbar.yaml,
# print a short table, write out/fourbar.csv and out/fourbar.svg. Then the statics of
# models/slider_crank_friction.yaml: the driving torque with friction to run the crank in +q
# and in -q, joint reactions and the dead zones over a crank turn (out/slider_crank_friction.csv,
# the force diagram .svg, and the torque against the angle and the polar diagrams of the ground
# bearings' loads, _drive.png and _bearings.png, plotted by gnuplot through --plots). Last, the dynamics of models/slider_crank_motor.yaml:
# the start-up of a motor-driven slider-crank against its load until the speed is periodic
# (out/slider_crank_motor.csv, .png). And an engine: the flywheel of the single-cylinder
# models/engine_single.yaml sized by the energy loop for C_s = 0.02 at 3000 rpm and checked by
# simulating its steady cycle (out/engine_single_*.csv).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
# Only the main job's packages and targets: no test suite, no benchmarks, no MPI, Simbody or
# LaTeX (scripts/test.sh installs and builds those).
MECHGEN_DEPS=main MECHGEN_BUILD_TESTS=OFF MECHGEN_BUILD_BENCHMARKS=OFF \
  bash scripts/build.sh fourbar_sweep slider_crank_friction_statics slider_crank_motor_simulate \
  engine_single_engine
mkdir -p out
./build/models/fourbar_sweep --steps 360 --csv out/fourbar.csv --svg out/fourbar.svg --table 8
echo
./build/models/slider_crank_friction_statics --steps 360 --table 6 --dead-zones \
  --csv out/slider_crank_friction.csv --svg out/slider_crank_friction.svg --plots out/slider_crank_friction
echo
./build/models/slider_crank_motor_simulate --t-end 20 --dt 0.002 --csv out/slider_crank_motor.csv
if command -v gnuplot >/dev/null; then
  gnuplot -e "csv='out/slider_crank_motor.csv'; png='out/slider_crank_motor.png'" \
    runtime/tools/plot_dynamics.gnuplot
  echo "wrote out/slider_crank_motor.png (start-up: crank angle and speed, torque, energies, reactions)"
fi
echo
./build/models/engine_single_engine flywheel --rpm 3000 --cs 0.02 --loop out/engine_single_loop.csv \
  --sweep out/engine_single_cs.csv --wittenbauer out/engine_single_wittenbauer.csv
echo
echo "quickstart: done in $(( $(date +%s) - start )) s (installing, building and running)."
# The four programs above are the per-model tools (mechgen_add_model): for these four answers they
# compile faster than the runtime compiled once (about 75 s of CPU against 340 s). For models of
# your own, build that runtime once; then `mechgen <command> MODEL` answers a new model in seconds.
echo "next: cmake --build build --target mechgen_view   # once; then, for any model file:"
echo "      ./build/generator/mechgen sweep my_linkage.yaml --steps 360 --csv out.csv --svg out.svg"
