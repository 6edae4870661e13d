#!/usr/bin/env bash
# Builds and runs the four-bar benchmark with repetitions; prints the median time per
# configuration of each method and the ratios the project targets:
#   mechgen continuation / hand-written closed form   (target <= 1.5)
#   Ceres autodiff (problem reused) / mechgen          (target >= 20)
# Usage: bench/run_fourbar.sh [build-dir] [repetitions]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
REPS=${2:-10}
if [ ! -f "$BUILD/build.ninja" ] && [ ! -f "$BUILD/Makefile" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$BUILD" --parallel 2 --target fourbar_bench
BIN=$(find "$BUILD" -name fourbar_bench -type f -perm -u+x | head -n 1)
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
print(f"four-bar, one configuration per 0.5 deg step (median CPU time of {data['benchmarks'][0].get('repetitions', '?')} repetitions)")
for name, t in med.items():
    print(f"  {name:<22} {t:10.1f} {unit[name]}")
def r(a, b): return med[a] / med[b]
print()
print(f"  mechgen / closed form          = {r('MechgenContinuation', 'ClosedForm'):6.2f}   (target <= 1.5)")
if 'MechgenClosedForm' in med:
    print(f"  generated dyad / closed form   = {r('MechgenClosedForm', 'ClosedForm'):6.2f}   (target <= 1.2)")
print(f"  Ceres autodiff / mechgen       = {r('CeresAutoDiffReused', 'MechgenContinuation'):6.1f}   (target >= 20)")
print(f"  Ceres analytic / mechgen       = {r('CeresAnalyticReused', 'MechgenContinuation'):6.1f}")
print(f"  Ceres new problem / mechgen    = {r('CeresNewProblem', 'MechgenContinuation'):6.1f}")
PY
