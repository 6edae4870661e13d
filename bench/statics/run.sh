#!/usr/bin/env bash
# Builds and runs the statics benchmark (bench/statics/statics_bench.cc) with repetitions;
# prints the median time per configuration of each method and the ratios the issue targets:
#   (3) reactions / (1) kinematics        (target <= 1.5)
#   (4) Newton–Euler LU / (3) reactions   (target >= 5)
# Usage: bash bench/statics/run.sh [build-dir] [repetitions]
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
REPS=${2:-10}
# Configured with the benchmarks (scripts/test.sh builds without them).
if [ ! -f "$BUILD/build.ninja" ] && [ ! -f "$BUILD/Makefile" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
else
  cmake -S . -B "$BUILD" -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
fi
cmake --build "$BUILD" --parallel 2 --target statics_bench
BIN=$(find "$BUILD" -name statics_bench -type f -perm -u+x | head -n 1)
JSON=$(mktemp)
trap 'rm -f "$JSON"' EXIT
"$BIN" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
       --benchmark_min_time=0.2 --benchmark_format=json --benchmark_out="$JSON" \
       --benchmark_out_format=json >/dev/null
python3 - "$JSON" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
med = {b["run_name"]: b["cpu_time"] for b in data["benchmarks"]
       if b.get("aggregate_name") == "median"}
unit = {b["run_name"]: b["time_unit"] for b in data["benchmarks"]}
label = {
    "Positions": "(0) positions",
    "Kinematics": "(1) positions + K + L",
    "Forces": "(2) + Q, drive",
    "Reactions": "(3) + 4 pin reactions",
    "Full": "(3+) + V, dV/dq",
    "StaticsOnly": "(3s) positions + K + (3)",
    "FullStiffness": "(3++) + d2V, stiffness",
    "NewtonEuler": "(4) positions + N-E LU",
    "NewtonEulerFixedLU": "(4') same, fixed-size LU",
    "NewtonEulerSolveOnly": "    N-E LU alone",
}
reps = data["benchmarks"][0].get("repetitions", "?")
print(f"fourbar_loaded statics, one configuration per 0.5 deg step (median CPU time of {reps} repetitions)")
for name, t in med.items():
    print(f"  {label.get(name, name):<26} {t:8.1f} {unit[name]}")
def r(a, b): return med[a] / med[b]
print()
print(f"  (2) / (1) forces / kinematics       = {r('Forces', 'Kinematics'):6.2f}")
print(f"  (3) / (1) reactions / kinematics    = {r('Reactions', 'Kinematics'):6.2f}   (target <= 1.5)")
print(f"  (3) / (2) reactions / forces        = {r('Reactions', 'Forces'):6.2f}")
print(f"  (4) / (3) Newton-Euler / reactions  = {r('NewtonEuler', 'Reactions'):6.2f}   (target >= 5)")
print(f"  (4') / (3) fixed-size LU / reactions = {r('NewtonEulerFixedLU', 'Reactions'):6.2f}")
print(f"  ((4) - (0)) / ((3) - (0)) from the same positions = {(med['NewtonEuler'] - med['Positions']) / (med['Reactions'] - med['Positions']):6.2f}")
print(f"  (4) / (3s) Newton-Euler / statics-only model = {r('NewtonEuler', 'StaticsOnly'):6.2f}   (no L: what statics needs)")
print(f"  (3+) / (1) with V and dV/dq        = {r('Full', 'Kinematics'):6.2f}")
print(f"  (3++) / (1) with EvalStiffness      = {r('FullStiffness', 'Kinematics'):6.2f}")
print(f"  N-E LU alone / ((3) - (1))          = {med['NewtonEulerSolveOnly'] / max(1e-9, med['Reactions'] - med['Kinematics']):6.2f}   (the statics part alone)")
PY
