#!/usr/bin/env bash
# Builds and runs the design-sensitivity benchmark (bench/design/design_bench.cc and
# trajectory_bench.cc) with repetitions, side by side in one run; prints the medians per
# configuration and issue 27's targets, per model with N design parameters:
#   (2) values + generated d/dp  <= 0.7 x (3) the Jet<double, N> instantiation of the values
#   (2)                          <= (1 + 0.5 N) x (1) the values alone
# and issue 46's through time (trajectory sensitivities, at the same tolerance):
#   forward sensitivities of one run <= 0.5 x the N + 1 simulations of forward differences on
#   the massive four-bar (N = 6), <= 0.35 x on the five-bar (N = 13);
#   the adjoint gradient of one scalar <= 4 simulations;
# with the simultaneous method (the sensitivities in the error test) beside the staggered one,
# the steps and evaluations of each, and the machine's load (uptime) before and after.
# Usage: bash bench/design/run.sh [build-dir] [repetitions] [benchmark filter regex]
#   (JOBS=1 to build with one job.)
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
REPS=${2:-5}
FILTER=${3:-.}
# Configured with the benchmarks (scripts/test.sh builds without them).
if [ ! -f "$BUILD/build.ninja" ] && [ ! -f "$BUILD/Makefile" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
else
  cmake -S . -B "$BUILD" -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
fi
cmake --build "$BUILD" --parallel "${JOBS:-2}" --target design_bench
BIN=$(find "$BUILD" -name design_bench -type f -perm -u+x | head -n 1)
JSON=$(mktemp)
trap 'rm -f "$JSON"' EXIT
echo "load before: $(uptime)"
"$BIN" --benchmark_filter="$FILTER" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
       --benchmark_min_time=0.2 --benchmark_format=json --benchmark_out="$JSON" \
       --benchmark_out_format=json >/dev/null
echo "load after:  $(uptime)"
python3 - "$JSON" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
med = {b["run_name"]: b["cpu_time"] for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
cnt = {b["run_name"]: b for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
unit = {b["run_name"]: b["time_unit"] for b in data["benchmarks"]}
reps = data["benchmarks"][0].get("repetitions", "?")
N = {"fourbar": 6, "watt_sixbar": 11}
if all(f"{k}/{m}" in med for m in N for k in ("Values", "Derivatives", "Jet")):
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
NT = {"design_fourbar_massive": (6, 0.5), "design_fivebar_massive": (13, 0.35)}
KEYS = ("Values", "Differences", "Sensitivities", "Simultaneous", "JetSensitivities", "Adjoint")
if all(f"Trajectory/{k}/{m}" in med for m in NT for k in KEYS):
    print(f"Trajectory sensitivities per run (median CPU time of {reps} repetitions; Dop853, rtol 1e-10, atol 1e-12)")
    def steps(key):
        c = cnt[key]
        return f"{int(c.get('steps', 0)):5d} steps, {int(c.get('rhs', 0)):6d} rhs" + (
            f", {int(c['partials']):5d} partials" if "partials" in c else "")
    for model, (n, target) in NT.items():
        v, d, s, si, sj, a = (med[f"Trajectory/{k}/{model}"] for k in KEYS)
        u = unit[f"Trajectory/Values/{model}"]
        print(f"  {model} (N = {n})")
        print(f"    one simulation of the values             {v:10.1f} {u}   {steps(f'Trajectory/Values/{model}')}")
        print(f"    N + 1 simulations (forward differences)  {d:10.1f} {u}")
        print(f"    sensitivities, staggered (not in the error test) {s:10.1f} {u}   {steps(f'Trajectory/Sensitivities/{model}')}")
        print(f"    sensitivities, simultaneous (in the error test)  {si:10.1f} {u}   {steps(f'Trajectory/Simultaneous/{model}')}")
        print(f"    staggered, f_q and f_qd by Jets          {sj:10.1f} {u}")
        k5 = f"Trajectory/Staggered5/{model}"
        if k5 in med:
            print(f"    staggered with 5 nodes (order 8)         {med[k5]:10.1f} {u}   {steps(k5)}   ({med[k5] / d:5.2f} x N + 1)")
        print(f"    adjoint gradient of one scalar           {a:10.1f} {u}   {steps(f'Trajectory/Adjoint/{model}')}")
        r, ri, ra = s / d, si / d, a / v
        print(f"    forward sensitivities / (N + 1 simulations) = {r:5.2f}   target <= {target:4.2f}   {'PASS' if r <= target else 'MISS'}"
              f"   (simultaneous {ri:5.2f}, by Jets {sj / d:5.2f})")
        print(f"    adjoint / one simulation = {a / v:5.2f}   target <= 4      {'PASS' if ra <= 4 else 'MISS'}"
              f"   (forward sensitivities / one simulation = {s / v:5.2f})")
        ev = {k: med.get(f"Trajectory/{k}/{model}") for k in ("StateRhs", "Partials", "Derivative", "JetDerivative")}
        if all(x is not None for x in ev.values()):
            ue = unit[f"Trajectory/Partials/{model}"]
            print(f"    one evaluation: state rhs {ev['StateRhs']:.1f} {ue}, partials f_q, f_qd, f_p {ev['Partials']:.1f} {ue}, "
                  f"simultaneous rhs {ev['Derivative']:.1f} {ue} (by Jets {ev['JetDerivative']:.1f} {ue})")
PY
