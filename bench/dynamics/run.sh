#!/usr/bin/env bash
# Builds and runs the dynamics benchmark of the massive four-bar (bench/dynamics), one run:
#   results/reference.txt     the reference theta(3 s) and its cross-check with Simbody
#   results/rhs.csv           one right-hand side: median CPU time per method
#   results/simulate.csv      3 s simulated per (method, tolerance): median CPU time,
#                             |theta(3 s) error|, steps, right-hand sides
#   results/energy_drift.csv  E(t) - E(0) against simulated time (tolerances 1e-6, 1e-9)
#   results/dynamics.txt      the tables and the ratios the project targets (issue 24, with
#                             PASS / MISS): generated rhs / hand-written <= 1.10, generated
#                             direction-cosine kinematics (SolveTrig + Coeffs) / hand-written <= 1.20
#   results/cpu_vs_error.svg, results/energy_drift.svg   the charts (gnuplot)
# With a Release build of Simbody 3.7 (bench/dynamics/build_simbody_release.sh <prefix>),
# pass its prefix as SIMBODY_RELEASE_DIR=<prefix> (or configure the build with
# -DMECHGEN_SIMBODY_RELEASE_DIR=<prefix>): dynamics_bench_simbody_release then runs too.
# Usage: [SIMBODY_RELEASE_DIR=<prefix>] bash bench/dynamics/run.sh [build-dir] [repetitions]
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
REPS=${2:-5}
OUT=bench/dynamics/results
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
TARGETS="dynamics_reference dynamics_bench"
if grep -q dynamics_bench_simbody_release "$BUILD/build.ninja" 2>/dev/null; then
  TARGETS="$TARGETS dynamics_bench_simbody_release"
fi
cmake --build "$BUILD" --parallel 2 --target $TARGETS
BIN_DIR="$BUILD/bench/dynamics"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

"$BIN_DIR/dynamics_reference" 2>/dev/null | tee "$OUT/reference.txt"
# CPodes prints its internal "mxstep" notices on stderr (it continues): kept out of the output.
"$BIN_DIR/dynamics_bench" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
    --benchmark_min_time=0.2 --benchmark_out="$TMP/main.json" --benchmark_out_format=json \
    >/dev/null 2>"$TMP/main.err" || { cat "$TMP/main.err"; exit 1; }
"$BIN_DIR/dynamics_bench" --drift_csv="$TMP/drift_main.csv" 2>/dev/null
JSONS="$TMP/main.json"
DRIFTS="$TMP/drift_main.csv"
if [ -x "$BIN_DIR/dynamics_bench_simbody_release" ]; then
  "$BIN_DIR/dynamics_bench_simbody_release" --benchmark_repetitions="$REPS" \
      --benchmark_report_aggregates_only=true --benchmark_min_time=0.2 \
      --benchmark_out="$TMP/release.json" --benchmark_out_format=json >/dev/null 2>"$TMP/rel.err" \
      || { cat "$TMP/rel.err"; exit 1; }
  "$BIN_DIR/dynamics_bench_simbody_release" --drift_csv="$TMP/drift_release.csv" 2>/dev/null
  JSONS="$JSONS $TMP/release.json"
  DRIFTS="$DRIFTS $TMP/drift_release.csv"
fi
{ head -n 1 "$TMP/drift_main.csv"; for f in $DRIFTS; do tail -n +2 "$f"; done; } > "$OUT/energy_drift.csv"

python3 - "$OUT" "$REPS" "$TMP" $JSONS <<'PY' | tee "$OUT/dynamics.txt"
import json, math, sys
out, reps, tmp, files = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
rhs, sim, context = {}, {}, {}
for f in files:
    data = json.load(open(f))
    for k in ("simbody_library", "reference_theta_3s"):
        context.setdefault(k, []).append(data["context"].get(k, "?"))
    # The medians; with one repetition there are no aggregates: the run itself.
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

print(f"massive four-bar (ground 4, crank 1, coupler 3.5, rocker 3; 2 kg/m bars; g = 9.81; from rest at 90 deg)")
print(f"median CPU time of {reps} repetitions; reference theta(3 s) = {context['reference_theta_3s'][0]} rad")
print(f"Simbody libraries: {', '.join(context['simbody_library'])}")
print()
print("(a) one right-hand side (positions + I + I' + Q + qdd), per configuration")
for k, v in rhs.items():
    print(f"  {k:<28} {v:8.1f} ns")
def ratio(a, b):
    return rhs[a] / rhs[b] if a in rhs and b in rhs else float("nan")
def target(label, a, b, limit):
    x = ratio(a, b)
    verdict = "PASS" if x <= limit else ("MISS" if math.isfinite(x) else "not measured")
    print(f"  {label:<38} = {x:5.2f}   target <= {limit:.2f} {verdict}")
if "Rhs/Generated" in rhs:
    print("  targets (issue 24)")
    target("generated rhs / hand-written rhs", "Rhs/Generated", "Rhs/Handwritten", 1.10)
    target("generated kinematics / hand-written", "Kinematics/GeneratedOnePass", "Kinematics/Handwritten", 1.20)
    print("  for reference")
    print(f"  generated kinematics / hand-written with its checks = {ratio('Kinematics/GeneratedOnePass', 'Kinematics/HandwrittenChecked'):5.2f}   (the same refusals, range checks, branch measure, Phi_phi)")
    print(f"  hand-written with the checks / hand-written = {ratio('Kinematics/HandwrittenChecked', 'Kinematics/Handwritten'):5.2f}   (the price of the checks alone)")
    print(f"  SolveTrig + Coeffs / hand-written kinematics = {ratio('Kinematics/GeneratedTrig', 'Kinematics/Handwritten'):5.2f}   (two calls)")
    print(f"  generated / generated kinematics     = {ratio('Rhs/Generated', 'Kinematics/Generated'):5.2f}   (Solve + Coeffs)")
    print(f"  generated / generated trig kinematics = {ratio('Rhs/Generated', 'Kinematics/GeneratedTrig'):5.2f}   (SolveTrig + Coeffs)")
if "Rhs/GeneratedThreeCalls" in rhs:
    print(f"  three calls / hand-written           = {ratio('Rhs/GeneratedThreeCalls', 'Rhs/Handwritten'):5.2f}   (SolveTrig + Coeffs + Dynamics)")
    print(f"  generated / hand-written kinematics  = {ratio('Rhs/Generated', 'Kinematics/Handwritten'):5.2f}")
if "Rhs/MinimalDynamics" in rhs:
    print(f"  runtime rhs / hand-written           = {ratio('Rhs/MinimalDynamics', 'Rhs/Handwritten'):5.2f}")
print(f"  textbook / hand-written              = {ratio('Rhs/Textbook', 'Rhs/Handwritten'):5.2f}")
print(f"  hand-written / hand-written kinematics = {ratio('Rhs/Handwritten', 'Kinematics/Handwritten'):5.2f}")
print()
print("(b) simulate 3 s: CPU time [us] / |theta(3 s) error| [rad] per tolerance")
w = 26
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
    pts = sorted((sim[(m, t)]["error"], sim[(m, t)]["cpu_us"]) for t in tols if (m, t) in sim
                 and sim[(m, t)]["error"] > 0 and math.isfinite(sim[(m, t)]["error"]))
    return pts
def time_at(m, err):
    """CPU time of method m at error err: log-log interpolation between its measured points."""
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
print("  at equal accuracy: Simbody's CPU time at the error mechgen reached (log-log interpolation")
print("  of Simbody's time against error; its fastest integrator there) / mechgen's CPU time")
ours = [m for m in methods if m.startswith("Mechgen") or m.startswith("Excess") or m.startswith("Hand")]
for ref in ("SimbodyRelease", "SimbodyDebian"):
    if not any(m.startswith(ref) for m in methods):
        print(f"  ({ref}: not measured)")
        continue
    print(f"  vs {ref}" + (" (target: mechgen minimal >= 300x)" if ref == "SimbodyRelease" else ""))
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
print()
print("  mechgen / hand-written EOM, the same integrator and tolerance (target <= 1.3)")
for m in methods:
    if m.startswith("Mechgen"):
        h = "Hand" + m[len("Mechgen"):]
        print("    " + m.ljust(w) + "".join((f"{sim[(m, t)]['cpu_us'] / sim[(h, t)]['cpu_us']:6.2f}"
              if (m, t) in sim and (h, t) in sim else "-").rjust(20) for t in tols))

# Charts.
import subprocess
with open(f"{tmp}/cpu_vs_error.dat", "w") as f:
    for m in methods:
        f.write(f"# {m}\n")
        for e, t in curve(m):
            f.write(f"{e:.6e} {t:.6e}\n")
        f.write("\n\n")
plots = ", ".join(f"'{tmp}/cpu_vs_error.dat' index {i} with linespoints lw 2 title '{m}'"
                  for i, m in enumerate(methods))
script = f"""
set terminal svg size 900,600 font 'sans,11'
set output '{out}/cpu_vs_error.svg'
set logscale xy
set format x '10^{{%L}}'
set format y '10^{{%L}}'
set xlabel '|theta(3 s) - reference| [rad]'
set ylabel 'CPU time for 3 s simulated [us]'
set title 'Massive four-bar, 3 s from rest: CPU time against error (tolerances 1e-4 .. 1e-10)'
set key outside right
set grid
plot {plots}
"""
subprocess.run(["gnuplot"], input=script, text=True, check=True)

drift = {}
for line in open(f"{out}/energy_drift.csv").read().splitlines()[1:]:
    m, tol, t, d = line.split(",")
    drift.setdefault((m, tol), []).append((float(t), abs(float(d))))
with open(f"{tmp}/energy_drift.dat", "w") as f:
    keys = list(drift)
    for k in keys:
        f.write(f"# {k[0]} {k[1]}\n")
        for t, d in drift[k]:
            if t > 0:
                f.write(f"{t:.2f} {max(d, 1e-17):.6e}\n")
        f.write("\n\n")
plots = ", ".join(f"'{tmp}/energy_drift.dat' index {i} with lines lw 2 dt {1 if k[1] == '1e-06' else 2} title '{k[0]} tol {k[1]}'"
                  for i, k in enumerate(keys))
script = f"""
set terminal svg size 900,600 font 'sans,11'
set output '{out}/energy_drift.svg'
set logscale y
set format y '10^{{%L}}'
set xlabel 'simulated time [s]'
set ylabel '|E(t) - E(0)| [J]'
set title 'Massive four-bar, energy drift (solid: tolerance 1e-6, dashed: 1e-9)'
set key outside right
set grid
plot {plots}
"""
subprocess.run(["gnuplot"], input=script, text=True, check=True)
print()
print(f"charts: {out}/cpu_vs_error.svg, {out}/energy_drift.svg")
PY
