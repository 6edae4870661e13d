#!/usr/bin/env bash
# Builds and runs the four-bar benchmark with repetitions; prints the median time per
# configuration of each method and, with PASS / MISS, the ratios the project targets now
# (issue 24), all from this one run (both sides of a ratio suffer the same machine noise):
#   mechgen continuation / hand-written closed form        (target <= 1.15)
#   generated dyad path (Solve + Coeffs) / closed form     (target <= 0.85)
#   runtime continuation / plain Newton loop, every model  (target <= 1.00)
#   through the model view / fixed-size, issue 43 (target <= 1.15 each): a sweep step
#   (MechgenContinuation, fourbar), a statics row (StaticsRows, slider_crank_friction) and a
#   simulation's right-hand side (RightHandSide, fourbar_massive; also chained as an
#   integrator's stages, RightHandSideChained, and per evaluation in a whole simulation,
#   Simulation). The sweep step and the
#   statics row as `mechgen sweep` and `mechgen statics` run these models: on the runtime
#   sized to their shape (core/view_sized.h, one input and two dependent coordinates; *Sized);
#   beside them, for reference, the same on the instantiation for any view (*View), which
#   models of other shapes run, and one statics::Solve at rest and moving (StaticsSolve*): where
#   the statics row's difference lies, per solve and per friction iteration.
# The Ceres ratios are printed for reference (the first issue's >= 20 is no longer a target).
# Usage: [BENCH_FILTER=<regex>] bench/run_fourbar.sh [build-dir] [repetitions]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
REPS=${2:-10}
# Configured with the benchmarks (scripts/test.sh builds without them).
if [ ! -f "$BUILD/build.ninja" ] && [ ! -f "$BUILD/Makefile" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
else
  cmake -S . -B "$BUILD" -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
fi
cmake --build "$BUILD" --parallel 2 --target fourbar_bench
BIN=$(find "$BUILD" -name fourbar_bench -type f -perm -u+x | head -n 1)
JSON=$(mktemp)
trap 'rm -f "$JSON"' EXIT
"$BIN" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
       --benchmark_min_time=0.2 --benchmark_format=json --benchmark_out="$JSON" \
       --benchmark_out_format=json ${BENCH_FILTER:+--benchmark_filter="$BENCH_FILTER"} >/dev/null
python3 - "$JSON" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
med = {b["run_name"]: b["cpu_time"] for b in data["benchmarks"]
       if b.get("aggregate_name") == "median"}
unit = {b["run_name"]: b["time_unit"] for b in data["benchmarks"]}
print(f"four-bar, one configuration per 0.5 deg step (median CPU time of {data['benchmarks'][0].get('repetitions', '?')} repetitions)")
for name, t in med.items():
    print(f"  {name:<26} {t:10.1f} {unit[name]}")
def r(a, b): return med[a] / med[b]
def verdict(x, limit): return "PASS" if x <= limit else "MISS"
def target(label, a, b, limit):
    if a not in med or b not in med:
        print(f"  {label:<44} (not measured: {a if a not in med else b} missing)")
        return
    x = r(a, b)
    print(f"  {label:<44} = {x:6.2f}   target <= {limit:<5.2f} {verdict(x, limit)}")
print()
print("  targets (issue 24)")
target("mechgen continuation / closed form", "MechgenContinuation", "ClosedForm", 1.15)
target("generated dyad / closed form", "MechgenClosedForm", "ClosedForm", 0.85)
models = [n.split("/", 1)[1] for n in med if n.startswith("Continuation/")]
for m in models:
    target(f"continuation / plain Newton ({m})", f"Continuation/{m}", f"PlainNewton/{m}", 1.00)
print("  targets (issue 43: through the model view / the fixed-size instantiation, side by side)")
target("sweep step, view / fixed (fourbar)", "MechgenContinuationSized", "MechgenContinuation", 1.15)
target("statics row, view / fixed (slider_crank_friction)", "StaticsRowsSized", "StaticsRows", 1.15)
target("right-hand side, view / fixed (fourbar_massive)", "RightHandSideView", "RightHandSide", 1.15)
# The same right-hand side read two more ways (each against the same 1.15): its calls chained as
# an integrator's stages chain them (each call's state reads the last call's output, so that the
# calls do not overlap: the call's latency, where the line above is its throughput over
# independent calls); and a whole free simulation (Dopri5, samples at every step), per
# evaluation of the right-hand side, the integrator and the samples included.
target("right-hand side chained, view / fixed", "RightHandSideChainedView", "RightHandSideChained", 1.15)
target("a simulation per evaluation, view / fixed", "SimulationView", "Simulation", 1.15)
if "SimulationView" in med and "Simulation" in med:
    rhs = {b["run_name"]: b.get("rhs") for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
    if rhs.get("Simulation") and rhs.get("SimulationView"):
        print(f"    (per evaluation: {med['Simulation'] / rhs['Simulation']:.1f} -> "
              f"{med['SimulationView'] / rhs['SimulationView']:.1f} {unit['Simulation']}, "
              f"{rhs['Simulation']:.0f} evaluations a run)")
print("  for reference: the instantiation for a view of any shape (models of other shapes run it)")
for label, a, b in [("sweep step, any-shape view / fixed (fourbar)", "MechgenContinuationView", "MechgenContinuation"),
                    ("statics row, any-shape view / fixed", "StaticsRowsView", "StaticsRows")]:
    if a in med and b in med:
        print(f"  {label:<44} = {r(a, b):6.2f}")
# Where the statics row's difference lies: one Solve at rest (one evaluation) and one moving (the
# friction iteration), sized view against fixed; the first difference is per solve, the second
# less the first per iteration.
solves = [("at rest, one evaluation", "StaticsSolveAtRestSized", "StaticsSolveAtRest"),
          ("moving, the friction iteration", "StaticsSolveMovingSized", "StaticsSolveMoving")]
if all(a in med and b in med for _, a, b in solves):
    print("  where the statics row's difference lies (sized view / fixed, one statics::Solve):")
    for label, a, b in solves:
        print(f"    {label:<42} = {r(a, b):6.2f}   ({med[b]:.1f} -> {med[a]:.1f} {unit[a]})")
print()
if "CeresAutoDiffReused" not in med:
    sys.exit(0)
print("  for reference (no target)")
print(f"  Ceres autodiff / mechgen       = {r('CeresAutoDiffReused', 'MechgenContinuation'):6.1f}")
print(f"  Ceres analytic / mechgen       = {r('CeresAnalyticReused', 'MechgenContinuation'):6.1f}")
print(f"  Ceres new problem / mechgen    = {r('CeresNewProblem', 'MechgenContinuation'):6.1f}")
PY
