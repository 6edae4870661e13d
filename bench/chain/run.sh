#!/usr/bin/env bash
# The N-chain scaling study: for N = 1 .. 128 and both emission strategies (blocks,
# monolithic), the generation time (median of 5 runs of `mechgen generate`), generated lines
# and operation counts, and the time per configuration of positions + K + L (Google
# Benchmark medians, both strategies side by side in one run). Writes
# bench/chain/results/{generation,time}.csv and chain.svg. Then the project's target on the
# chain (issue 24), from fourbar_bench in one run, with PASS / MISS:
#   runtime continuation (PositionSolver::MoveTo) / plain Newton loop on chain_4 and chain_8
#   (target <= 1.00)
# Usage: bash bench/chain/run.sh [build-dir] [repetitions]
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
cmake --build "$BUILD" --parallel 2 --target mechgen chain_bench fourbar_bench >/dev/null
OUT=bench/chain/results
mkdir -p "$OUT"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
stamp="# $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(date -u '+%F %H:%M UTC')"
MECHGEN=$(find "$BUILD" -name mechgen -type f -perm -u+x | head -n 1)

{
  echo "$stamp"
  echo "N,strategy,generation_ms,header_lines,source_lines,phi_ops,positions_ops,coefficient_ops"
  for N in 1 2 4 8 16 32 64 128; do
    bash tools/make_chain.sh "$N" 2 "$tmp/chain_$N.yaml"
    for strategy in blocks monolithic; do
      ms=()
      for run in 1 2 3 4 5; do
        start=$(date +%s%N)
        "$MECHGEN" generate "$tmp/chain_$N.yaml" --strategy "$strategy" --out-dir "$tmp/$strategy" --quiet
        end=$(date +%s%N)
        ms+=($(( (end - start) / 1000000 )))
      done
      median=$(printf '%s\n' "${ms[@]}" | sort -n | sed -n 3p)
      h="$tmp/$strategy/chain_$N.h"
      ops=$(grep -m1 'Operation counts' "$h")
      phi=$(echo "$ops" | sed -E 's/.*EvalPhi ([0-9]+).*/\1/')
      pos=$(echo "$ops" | sed -E 's/.*SolvePositions ([0-9]+).*/\1/')
      coef=$(echo "$ops" | sed -E 's/.*EvalCoefficients ([0-9]+).*/\1/')
      echo "$N,$strategy,$median,$(wc -l < "$h"),$(wc -l < "$tmp/$strategy/chain_$N.cc"),$phi,$pos,$coef"
    done
  done
} > "$OUT/generation.csv"

BIN=$(find "$BUILD" -name chain_bench -type f -perm -u+x | head -n 1)
"$BIN" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true --benchmark_min_time=0.1 \
       --benchmark_format=json --benchmark_out="$tmp/bench.json" --benchmark_out_format=json >/dev/null
python3 - "$tmp/bench.json" "$OUT" "$stamp" <<'PY'
import json, sys
data, out, stamp = json.load(open(sys.argv[1])), sys.argv[2], sys.argv[3]
med = {}
for b in data["benchmarks"]:
    if b.get("aggregate_name") == "median":
        strategy, n = b["run_name"].split("/")
        med[(strategy, int(n))] = b["cpu_time"] * {"ns": 1, "us": 1e3, "ms": 1e6}[b["time_unit"]]
ns = sorted({n for _, n in med})
with open(f"{out}/time.csv", "w") as f:
    f.write(stamp + "\nN,blocks_ns,monolithic_ns,monolithic_over_blocks\n")
    for n in ns:
        f.write(f"{n},{med[('blocks', n)]:.1f},{med[('monolithic', n)]:.1f},{med[('monolithic', n)] / med[('blocks', n)]:.2f}\n")
print("N-chain, time per configuration (positions + K + L), median CPU time")
print(f"{'N':>5} {'blocks ns':>12} {'per loop':>9} {'monolithic ns':>14} {'mono/blocks':>12}")
for n in ns:
    b, m = med[("blocks", n)], med[("monolithic", n)]
    print(f"{n:>5} {b:12.0f} {b / n:9.1f} {m:14.0f} {m / b:12.1f}")
PY
column -s, -t < "$OUT/generation.csv" | sed 1d
gnuplot <<GP
set terminal svg size 1100,420 dynamic font "sans,12"
set output "$OUT/chain.svg"
set datafile separator ","
set multiplot layout 1,3 title "N four-bar loops in series (tools/make_chain.sh) — $(echo "$stamp" | sed 's/^# //')"
set logscale xy
set key top left
set grid
set xlabel "N (loops)"
set ylabel "ns per configuration (positions + K + L)"
set title "time per configuration"
plot "$OUT/time.csv" skip 2 using 1:2 with linespoints title "blocks (closed-form dyads)", \
     "$OUT/time.csv" skip 2 using 1:3 with linespoints title "monolithic (Newton, dense LU)"
set ylabel "ms"
set title "generation time (mechgen generate)"
plot "< grep ',blocks,' $OUT/generation.csv" using 1:3 with linespoints title "blocks", \
     "< grep ',monolithic,' $OUT/generation.csv" using 1:3 with linespoints title "monolithic"
set ylabel "lines / operations"
set title "generated code size"
plot "< grep ',blocks,' $OUT/generation.csv" using 1:4 with linespoints title "header lines (blocks)", \
     "< grep ',blocks,' $OUT/generation.csv" using 1:(\$7+\$8) with linespoints title "ops SolvePositions + EvalCoefficients (blocks)", \
     "< grep ',monolithic,' $OUT/generation.csv" using 1:(\$7+\$8) with linespoints title "ops per Newton iteration + EvalCoefficients (monolithic)"
unset multiplot
GP
echo "wrote $OUT/generation.csv $OUT/time.csv $OUT/chain.svg"

# The target on the chain: the runtime's continuation against a plain Newton loop (both in
# fourbar_bench, side by side in one run).
FOURBAR=$(find "$BUILD" -name fourbar_bench -type f -perm -u+x | head -n 1)
"$FOURBAR" --benchmark_filter='^(Continuation|PlainNewton)/chain_' --benchmark_repetitions="$REPS" \
    --benchmark_report_aggregates_only=true --benchmark_min_time=0.2 \
    --benchmark_out="$tmp/runtime.json" --benchmark_out_format=json >/dev/null
python3 - "$tmp/runtime.json" <<'PY'
import json, sys
med = {b["run_name"]: b["cpu_time"] for b in json.load(open(sys.argv[1]))["benchmarks"]
       if b.get("aggregate_name") == "median"}
print("runtime on the chain, median CPU time per 0.5 deg step")
for m in sorted({n.split("/", 1)[1] for n in med}):
    c, n = med[f"Continuation/{m}"], med[f"PlainNewton/{m}"]
    verdict = "PASS" if c / n <= 1.0 else "MISS"
    print(f"  {m:<8} continuation {c:8.1f} ns, plain Newton {n:8.1f} ns: "
          f"continuation / plain Newton = {c / n:5.2f}   target <= 1.00 {verdict}")
PY
