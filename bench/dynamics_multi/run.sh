#!/usr/bin/env bash
# Builds and runs the five-bar robot's pick-and-place benchmark (bench/dynamics_multi), one run:
#   results/rhs.csv             one right-hand side: median CPU time per method
#   results/simulate.csv        the 1 s cycle per (method, tolerance): median CPU time,
#                               max |q(1 s) - reference|, steps, right-hand sides
#   results/dynamics_multi.txt  the tables and the ratios at equal accuracy
# With a Release build of Simbody 3.7 (bench/dynamics/build_simbody_release.sh <prefix>), pass
# SIMBODY_RELEASE_DIR=<prefix>: dynamics_multi_bench_simbody_release then runs too.
# Usage: [SIMBODY_RELEASE_DIR=<prefix>] bash bench/dynamics_multi/run.sh [build-dir] [repetitions]
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
REPS=${2:-5}
OUT=bench/dynamics_multi/results
mkdir -p "$OUT"
# Configured with the benchmarks (scripts/test.sh builds without them).
if [ ! -f "$BUILD/build.ninja" ] && [ ! -f "$BUILD/Makefile" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
else
  cmake -S . -B "$BUILD" -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
fi
if [ -n "${SIMBODY_RELEASE_DIR:-}" ]; then
  cmake "$BUILD" -DMECHGEN_SIMBODY_RELEASE_DIR="$SIMBODY_RELEASE_DIR" >/dev/null
fi
TARGETS="dynamics_multi_bench"
if grep -q dynamics_multi_bench_simbody_release "$BUILD/build.ninja" 2>/dev/null; then
  TARGETS="$TARGETS dynamics_multi_bench_simbody_release"
fi
cmake --build "$BUILD" --parallel 2 --target $TARGETS
BIN_DIR="$BUILD/bench/dynamics_multi"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# CPodes prints its "mxstep" notices on stderr (it continues): kept out of the output.
"$BIN_DIR/dynamics_multi_bench" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
    --benchmark_min_time=0.2 --benchmark_out="$TMP/main.json" --benchmark_out_format=json \
    >/dev/null 2>"$TMP/main.err" || { cat "$TMP/main.err"; exit 1; }
JSONS="$TMP/main.json"
if [ -x "$BIN_DIR/dynamics_multi_bench_simbody_release" ]; then
  "$BIN_DIR/dynamics_multi_bench_simbody_release" --benchmark_repetitions="$REPS" \
      --benchmark_report_aggregates_only=true --benchmark_min_time=0.2 \
      --benchmark_out="$TMP/release.json" --benchmark_out_format=json >/dev/null 2>"$TMP/rel.err" \
      || { cat "$TMP/rel.err"; exit 1; }
  JSONS="$JSONS $TMP/release.json"
fi

python3 - "$OUT" "$REPS" $JSONS <<'PY' | tee "$OUT/dynamics_multi.txt"
import json, math, sys
out, reps, files = sys.argv[1], sys.argv[2], sys.argv[3:]
rhs, sim, context = {}, {}, {}
for f in files:
    data = json.load(open(f))
    for k in ("simbody_library", "reference_q_1s", "reference_vs_simbody_rkmerson_1e-12"):
        context.setdefault(k, []).append(data["context"].get(k, "?"))
    has_median = {b["run_name"] for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
    for b in data["benchmarks"]:
        name = b["run_name"]
        if b.get("error_occurred"):
            print(f"  {name}: {b.get('error_message')}")
            continue
        if b.get("aggregate_name") != "median" and (name in has_median or b.get("run_type") == "aggregate"):
            continue
        if name.startswith("Simulate/"):
            _, method, tol = name.split("/")
            sim[(method, tol)] = dict(cpu_us=b["cpu_time"], error=b.get("error", float("nan")),
                                      steps=b.get("steps", 0), rhs=b.get("rhs", 0))
        else:
            rhs[name] = b["cpu_time"]
methods = []
for (m, _) in sim:
    if m not in methods:
        methods.append(m)
tols = sorted({t for (_, t) in sim}, key=lambda t: -float(t))
with open(f"{out}/rhs.csv", "w") as f:
    f.write("method,cpu_ns\n")
    for k, v in rhs.items():
        f.write(f"{k},{v:.2f}\n")
with open(f"{out}/simulate.csv", "w") as f:
    f.write("method,tolerance,cpu_us,error,steps,rhs_evaluations\n")
    for m in methods:
        for t in tols:
            if (m, t) in sim:
                r = sim[(m, t)]
                f.write(f"{m},{t},{r['cpu_us']:.3f},{r['error']:.3e},{r['steps']:.0f},{r['rhs']:.0f}\n")

print("five-bar robot (models/fivebar_robot.yaml), pick-and-place cycle of 1 s under PD control")
print(f"median CPU time of {reps} repetitions; reference q(1 s) = {context['reference_q_1s'][0]} rad "
      f"(mechgen Dop853 1e-13 restarted at the breaks; Simbody RKMerson 1e-12 differs by {context['reference_vs_simbody_rkmerson_1e-12'][0]})")
print(f"Simbody libraries: {', '.join(context['simbody_library'])}")
print()
print("(a) one right-hand side (positions + I + h + Q + PD torques + qdd), per configuration")
for k, v in rhs.items():
    if not k.startswith("Chain/"):
        print(f"  {k:<22} {v:9.1f} ns")
for ref in ("Rhs/SimbodyRelease", "Rhs/SimbodyDebian"):
    if ref in rhs and "Rhs/Mechgen" in rhs:
        print(f"  {ref[4:]} / mechgen = {rhs[ref] / rhs['Rhs/Mechgen']:7.1f}x")
if "Rhs/ControlLawOnly" in rhs and "Rhs/Mechgen" in rhs:
    print(f"  (the control law, paid by both, is {rhs['Rhs/ControlLawOnly'] / rhs['Rhs/Mechgen'] * 100:.0f}% of mechgen's right-hand side)")
print()
print("(b) the N-loop chain (make_dyn_chain.sh: N massive crank-rocker loops in series, one input):")
print("    one right-hand side [ns]; growth exponent p of time ~ N^p between consecutive N")
chains = {}
for k, v in rhs.items():
    if k.startswith("Chain/"):
        _, who, n = k.split("/")
        chains.setdefault(who, {})[int(n)] = v
ns = sorted({n for d in chains.values() for n in d})
print("  " + "N".ljust(16) + "".join(str(n).rjust(12) for n in ns))
for who, d in chains.items():
    print("  " + who.ljust(16) + "".join((f"{d[n]:.0f}" if n in d else "-").rjust(12) for n in ns))
    print("  " + "  growth p".ljust(16) + "".rjust(12) + "".join(
        (f"{math.log(d[b] / d[a]) / math.log(b / a):.2f}" if a in d and b in d else "-").rjust(12)
        for a, b in zip(ns, ns[1:])))
for who in chains:
    if who != "Mechgen" and "Mechgen" in chains:
        print("  " + f"{who}/Mechgen".ljust(16) + "".join(
            (f"{chains[who][n] / chains['Mechgen'][n]:.0f}x" if n in chains[who] and n in chains["Mechgen"] else "-").rjust(12)
            for n in ns))
print()
print("(c) the 1 s cycle: CPU time [us] / max |q(1 s) error| [rad] per tolerance")
w = 32
print("  " + "method".ljust(w) + "".join(t.rjust(20) for t in tols))
for m in methods:
    row = "  " + m.ljust(w)
    for t in tols:
        r = sim.get((m, t))
        row += (f"{r['cpu_us']:9.1f} / {r['error']:7.1e}" if r else "-").rjust(20)
    print(row)
print()
print("  right-hand sides per simulation (Simbody: realizations)")
for m in methods:
    print("  " + m.ljust(w) + "".join((f"{sim[(m, t)]['rhs']:.0f}" if (m, t) in sim else "-").rjust(20) for t in tols))

def curve(m):
    return sorted((sim[(m, t)]["error"], sim[(m, t)]["cpu_us"]) for t in tols if (m, t) in sim
                  and sim[(m, t)]["error"] > 0 and math.isfinite(sim[(m, t)]["error"]))
def time_at(m, err):
    pts = curve(m)
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e0 <= err <= e1:
            if e1 == e0:
                return min(t0, t1)
            a = (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0)))
    return None
def best_time(prefix, err):
    ts = [(time_at(m, err), m) for m in methods if m.startswith(prefix)]
    ts = [(t, m) for t, m in ts if t is not None]
    return min(ts) if ts else (None, None)
print()
print("  at equal accuracy: Simbody's CPU time at the error mechgen reached (log-log interpolation of")
print("  Simbody's time against error; its fastest integrator there) / mechgen's CPU time")
ours = [m for m in methods if m.startswith("Mechgen")]
for ref in ("SimbodyRelease", "SimbodyDebian"):
    if not any(m.startswith(ref) for m in methods):
        print(f"  ({ref}: not measured)")
        continue
    print(f"  vs {ref}" + (" (target: >= 100x)" if ref == "SimbodyRelease" else ""))
    for m in ours:
        row = "    " + m.ljust(w)
        for t in tols:
            r = sim.get((m, t))
            if r is None:
                row += "-".rjust(20)
                continue
            ts, sm = best_time(ref, r["error"])
            row += (f"{ts / r['cpu_us']:8.0f}x {sm[len(ref):]:<10}" if ts else "out of range").rjust(20)
        print(row)
PY
echo | tee -a "$OUT/dynamics_multi.txt"
python3 bench/dynamics_multi/frontier.py "$OUT/simulate.csv" | tee -a "$OUT/dynamics_multi.txt"
