#!/usr/bin/env bash
# Builds and runs the design-sensitivity benchmark (bench/design/design_bench.cc) with
# repetitions, side by side in one run; prints the medians per configuration and issue 27's
# targets, per model with N design parameters:
#   (2) values + generated d/dp  <= 0.7 x (3) the Jet<double, N> instantiation of the values
#   (2)                          <= (1 + 0.5 N) x (1) the values alone
# and the cost of trajectory sensitivities (one run of the forward sensitivity equations)
# against the N + 1 simulations of forward differences (reported; the issue sets no target).
# Usage: bash bench/design/run.sh [build-dir] [repetitions]
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
REPS=${2:-5}
# Configured with the benchmarks (scripts/test.sh builds without them).
if [ ! -f "$BUILD/build.ninja" ] && [ ! -f "$BUILD/Makefile" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
else
  cmake -S . -B "$BUILD" -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
fi
cmake --build "$BUILD" --parallel 2 --target design_bench
BIN=$(find "$BUILD" -name design_bench -type f -perm -u+x | head -n 1)
JSON=$(mktemp)
trap 'rm -f "$JSON"' EXIT
"$BIN" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
       --benchmark_min_time=0.2 --benchmark_format=json --benchmark_out="$JSON" \
       --benchmark_out_format=json >/dev/null
python3 - "$JSON" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
med = {b["run_name"]: b["cpu_time"] for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
unit = {b["run_name"]: b["time_unit"] for b in data["benchmarks"]}
reps = data["benchmarks"][0].get("repetitions", "?")
N = {"fourbar": 6, "watt_sixbar": 11}
print(f"Design sensitivities per configuration (median CPU time of {reps} repetitions, one run)")
for model, n in N.items():
    v, d, j = (med[f"{k}/{model}"] for k in ("Values", "Derivatives", "Jet"))
    u = unit[f"Values/{model}"]
    print(f"  {model} (N = {n} design parameters)")
    print(f"    (1) values                    {v:8.1f} {u}")
    print(f"    (2) values + generated d/dp   {d:8.1f} {u}")
    print(f"    (3) Jet<double, {n}> values     {j:8.1f} {u}")
    r1, r2 = d / j, d / v
    print(f"    (2) / (3) = {r1:5.2f}   target <= 0.7          {'PASS' if r1 <= 0.7 else 'MISS'}")
    print(f"    (2) / (1) = {r2:5.2f}   target <= 1 + 0.5 N = {1 + 0.5 * n:4.1f}   {'PASS' if r2 <= 1 + 0.5 * n else 'MISS'}")
NT = {"design_fourbar_massive": 6, "design_fivebar_massive": 13}
if all(f"Trajectory/Values/{m}" in med for m in NT):
    print("Trajectory sensitivities per run (median CPU time; Dop853, rtol 1e-10, atol 1e-12)")
    for model, n in NT.items():
        v, d, s, sj = (med[f"Trajectory/{k}/{model}"] for k in ("Values", "Differences", "Sensitivities", "JetSensitivities"))
        u = unit[f"Trajectory/Values/{model}"]
        print(f"  {model} (N = {n})")
        print(f"    one simulation of the values            {v:10.1f} {u}")
        print(f"    N + 1 simulations (forward differences) {d:10.1f} {u}")
        print(f"    forward sensitivity equations, one run  {s:10.1f} {u}   (f_q, f_qd generated)")
        print(f"    the same with f_q, f_qd by Jets         {sj:10.1f} {u}")
        print(f"    sensitivities / (N + 1 simulations) = {s / d:5.2f} (by Jets {sj / d:5.2f}); / one simulation = {s / v:5.2f}")
        e, ej = (med[f"Trajectory/{k}/{model}"] for k in ("Derivative", "JetDerivative"))
        ue = unit[f"Trajectory/Derivative/{model}"]
        print(f"    one evaluation of the right-hand side   {e:10.1f} {ue} (f_q, f_qd by Jets: {ej:.1f} {ue})")
PY
