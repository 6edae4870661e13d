#!/usr/bin/env bash
# Renders the engine charts of docs/pictures (engine_*.png) from the <model>_engine commands:
#   tools/engine_charts.sh [build-dir]
# Needs engine_single_engine, engine_inline4_engine and engine_v8_engine built
# (ninja -C build engine_single_engine engine_inline4_engine engine_v8_engine) and gnuplot.
# Every chart at 3000 rpm with the default pressure law (polytropic cycle, Wiebe heat release
# of 800 J per cylinder and cycle); the flywheel for C_s = 0.02.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
out="$root/docs/pictures"
plot="$root/tools/plot_engine.gnuplot"
mkdir -p "$out"
command -v gnuplot > /dev/null || { echo "engine_charts.sh: gnuplot not found" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
chart() {  # chart csv png title
  gnuplot -e "chart='$1'; csv='$2'; png='$out/$3'; title='$4'" "$plot"
  echo "wrote $out/$3"
}
for m in single inline4 v8; do
  "$build/models/engine_${m}_engine" cycle --rpm 3000 --csv "$tmp/$m.csv" > /dev/null
  chart torque "$tmp/$m.csv" "engine_${m}_torque.png" "engine_$m at 3000 rpm: crank torque"
done
chart polar "$tmp/single.csv" engine_single_crankpin_polar.png "engine_single at 3000 rpm: crank pin load"
chart bearings "$tmp/single.csv" engine_single_bearings_polar.png "engine_single at 3000 rpm: bearing loads"
chart shaking "$tmp/single.csv" engine_single_shaking.png "engine_single at 3000 rpm: shaking force"
chart shaking_angle "$tmp/inline4.csv" engine_inline4_shaking.png "engine_inline4 at 3000 rpm: shaking force (secondary)"
"$build/models/engine_single_engine" flywheel --rpm 3000 --cs 0.02 --loop "$tmp/loop.csv" \
  --sweep "$tmp/sweep.csv" --wittenbauer "$tmp/witt.csv" > /dev/null
chart loop "$tmp/loop.csv" engine_single_energy_loop.png "engine_single at 3000 rpm: energy loop"
chart cs "$tmp/sweep.csv" engine_single_cs_flywheel.png "engine_single at 3000 rpm: C_s against the flywheel"
chart wittenbauer "$tmp/witt.csv" engine_single_wittenbauer.png "engine_single, C_s = 0.02: Wittenbauer diagram"
"$build/models/engine_single_engine" runup --rpm 3000 --idle-rpm 750 --csv "$tmp/runup.csv" > /dev/null
chart runup "$tmp/runup.csv" engine_single_runup.png "engine_single: run-up from 750 rpm to 3000 rpm"
