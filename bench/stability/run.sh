#!/usr/bin/env bash
# Runs the stability study and draws its charts.
#   bash bench/stability/run.sh [build-dir]      # default: build
# Writes bench/stability/results/stability.csv (with a '#' header naming machine, date and
# commit) and one SVG per case, results/<case>.svg: error of phi, K and L against the
# distance to the singular configuration, one line per method (gnuplot's svg terminal).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
out=bench/stability/results
mkdir -p "$out"
# Configured with the benchmarks (scripts/test.sh builds without them).
if [ ! -f "$build/build.ninja" ] && [ ! -f "$build/Makefile" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
else
  cmake -S . -B "$build" -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
fi
cmake --build "$build" --target stability_bench
{
  echo "# mechgen stability study (bench/stability/stability_bench.cc), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "# machine: $(uname -sm), $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'); compiler: $(${CXX:-c++} --version | head -1)"
  echo "# date: $(date -u +%Y-%m-%d)"
  "$build/bench/stability/stability_bench"
} > "$out/stability.csv"
for case in toggle change_in change_through; do
  gnuplot -e "csv='$out/stability.csv'; case='$case'; out='$out/$case.svg'" bench/stability/plot.gp
done
echo "wrote $out/stability.csv and $out/{toggle,change_in,change_through}.svg"
