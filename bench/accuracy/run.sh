#!/usr/bin/env bash
# Regenerates every figure and data file of bench/accuracy/results/ (issue 6):
#   1. builds accuracy_bench and mechgen in BUILD (configures it if needed);
#   2. runs accuracy_bench: the errors of every method against tests/reference/data/*.csv
#      (one sweep each), then the Google Benchmark timings (median CPU time of REPS
#      repetitions, every method of every model in the same run);
#   3. merges everything into CSV files stamped with the machine and the date, and draws the
#      SVG figures with gnuplot.
# The N-chain's generation time, code size and time per configuration against N for both
# emission strategies are bench/chain/run.sh's (bench/chain/results/chain.svg); this script
# adds every method at N = 2, 4, 8, 16 against the references (results/chain_methods.*).
# Usage: bash bench/accuracy/run.sh [build-dir] [repetitions]     (defaults: build 5)
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$PWD
BUILD=${1:-build}
REPS=${2:-5}
RES=$ROOT/bench/accuracy/results
mkdir -p "$RES"
command -v gnuplot >/dev/null || { echo "run.sh: gnuplot is missing (apt-get install gnuplot-nox)"; exit 1; }

# Configured with the benchmarks (scripts/test.sh builds without them).
if [ ! -f "$BUILD/build.ninja" ] && [ ! -f "$BUILD/Makefile" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
else
  cmake -S . -B "$BUILD" -DMECHGEN_BUILD_BENCHMARKS=ON >/dev/null
fi
cmake --build "$BUILD" --parallel 2 --target accuracy_bench mechgen
BIN=$(find "$BUILD" -name accuracy_bench -type f -perm -u+x | head -n 1)
MECHGEN=$(find "$BUILD" -name mechgen -type f -perm -u+x | head -n 1)

TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
STAMP="# machine: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'); $(date -u '+%Y-%m-%d %H:%M UTC'); mechgen $(git rev-parse --short HEAD 2>/dev/null || echo '?')"

echo "run.sh: errors and timings ($REPS repetitions) ..."
"$BIN" --errors_dir="$TMP" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
       --benchmark_min_time=0.1 --benchmark_format=json --benchmark_out="$TMP/bench.json" \
       --benchmark_out_format=json >/dev/null

python3 - "$TMP" "$RES" "$BUILD" "$STAMP" <<'PY'
import csv, glob, json, math, os, re, sys
tmp, res, build, stamp = sys.argv[1:5]
data = json.load(open(os.path.join(tmp, "bench.json")))
med = {b["run_name"]: b["cpu_time"] * {"ns": 1, "us": 1e3, "ms": 1e6}[b["time_unit"]]
       for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
models = sorted({k.split("/")[0] for k in med if not k.startswith("cost/")})
gp = []  # gnuplot commands
gp.append('set terminal svg size 1200,420 dynamic enhanced font "sans,11" background "white"')
gp.append('set datafile separator ","')
gp.append('set logscale xy; set format y "10^{%L}"; set grid')

def fmt(x):
    return "nan" if x is None else f"{x:.4g}"

# --- per model: time against max error; error along the sweep with cond ---
for m in models:
    mt = m.replace("_", "\\\\_")  # gnuplot enhanced text: a literal underscore
    err_file = os.path.join(tmp, f"{m}_errors.csv")
    rows = []
    errs = {}
    head = ""
    if os.path.exists(err_file):
        lines = open(err_file).read().splitlines()
        head = lines[0]
        for r in csv.DictReader(l for l in lines if not l.startswith("#")):
            errs[r["method"]] = [float(r["max_pos"]), float(r["max_K"]), float(r["max_L"]), int(r["refused"])]
    out = os.path.join(res, f"{m}_tradeoff.csv")
    with open(out, "w") as f:
        f.write(stamp + "\n")
        f.write(f"# {m}: median CPU time per configuration (Google Benchmark) and max error over the reference sweep\n")
        if head: f.write(head + "\n")
        f.write("method,ns,max_pos,max_K,max_L,label,refused\n")
        for k, t in med.items():
            if not k.startswith(m + "/"): continue
            meth = k.split("/", 1)[1]
            e = errs.get(meth, [None] * 4)
            # errors of exactly 0 (bit-identical) are drawn at 1e-17, above 1e6 at 1e6
            f.write(f"{meth},{t:.4g}," + ",".join(fmt(x) for x in e[:3]) + "," + meth.replace("_", " ") +
                    f",{fmt(e[3])}\n")
    if not errs: continue
    gp.append(f'set output "{res}/{m}_tradeoff.svg"')
    gp.append('set multiplot layout 1,3 title "' + mt + ': time per configuration vs max error over the sweep (' + stamp.split(";")[0][2:].replace("_", " ") + ')"')
    for col, what in ((3, "positions (rad, length/l_{max})"), (4, "K (rel.)"), (5, "L (rel.)")):
        gp.append(f'set xlabel "CPU time per configuration [ns]"; set ylabel "max error of {what}"; set yrange [1e-17:1e6]')
        gp.append(f'plot "{out}" using 2:(column({col}) > 1e6 ? 1e6 : (column({col}) < 1e-17 ? 1e-17 : column({col}))) with points pt 7 ps 0.8 notitle, '
                  f'"" using 2:(column({col}) > 1e6 ? 1e6 : (column({col}) < 1e-17 ? 1e-17 : column({col}))):(stringcolumn(6)) with labels font ",7" offset char 0,0.6 notitle')
    gp.append("unset multiplot; unset yrange")
    # sweep figure: selected methods, error along the sweep and cond on y2
    sweep = os.path.join(tmp, f"{m}_sweep.csv")
    lines = open(sweep).read().splitlines()
    with open(os.path.join(res, f"{m}_sweep.csv"), "w") as f:
        f.write(stamp + "\n" + "\n".join(lines) + "\n")
    header = [l for l in lines if not l.startswith("#")][0].split(",")
    chosen = ["closed_form", "dyads", "monolithic", "runtime", "newton_symbolic", "ceres_analytic",
              "fd_h1e-5", "ode_rk4", "ode_rk4_newton10", "float_newton", "float_dyads"]
    gp.append(f'set output "{res}/{m}_sweep.svg"')
    gp.append('set terminal svg size 1500,450 dynamic enhanced font "sans,11" background "white"')
    gp.append(f'set multiplot layout 1,3 title "{mt}: error along the sweep (left axis) and cond_1(Phi_phi) (right axis, grey)"')
    gp.append('unset logscale x; set logscale y; set y2tics; set logscale y2; set format y2 "10^{%L}"; set key bottom right font ",8"')
    sweep_path = os.path.join(res, f"{m}_sweep.csv")
    for what in ("pos", "K", "L"):
        parts = []
        for meth in chosen:
            name = f"{meth}:{what}"
            if name not in header: continue
            c = header.index(name) + 1
            parts.append(f'"{sweep_path}" using 1:(column({c}) < 1e-17 ? 1e-17 : column({c})) with lines title "{meth.replace("_", " ")}"')
        parts.append(f'"{sweep_path}" using 1:2 axes x1y2 with lines lc rgb "#aaaaaa" lw 3 title "cond"')
        gp.append(f'set xlabel "{ "first input q0 [deg]" }"; set ylabel "error of {what}"; set y2label "cond_1(Phi_phi)"; set yrange [1e-17:1e3]')
        gp.append("plot " + ", ".join(parts))
    gp.append("unset multiplot; unset y2tics; unset y2label; unset logscale y2; set logscale xy; unset yrange")
    gp.append('set terminal svg size 1200,420 dynamic enhanced font "sans,11" background "white"; set key default')

# --- the cost of asking for more ---
variants = [("fourbar_pos", "positions"), ("fourbar_k", "+ K"), ("fourbar_kl", "+ L"), ("fourbar_klp", "+ point P")]
cost = os.path.join(res, "cost.csv")
with open(cost, "w") as f:
    f.write(stamp + "\n")
    f.write("# fourbar asking for more outputs (bench/accuracy/models): generated operation counts and median CPU time per configuration\n")
    f.write("# lean: Newton on EvalPhi (step test 1e-9) + EvalCoefficients; runtime: PositionSolver::MoveTo (numeric K, L when the model has none)\n")
    f.write("variant,label,ops_EvalPhi,ops_EvalCoefficients,lean_ns,runtime_ns\n")
    for i, (v, label) in enumerate(variants):
        hdr = glob.glob(os.path.join(build, "**", f"{v}.h"), recursive=True)
        ops = ["nan", "nan"]
        if hdr:
            text = open(hdr[0]).read()
            a = re.search(r"EvalPhi (\d+)", text); b = re.search(r"EvalCoefficients (\d+)", text)
            ops = [a.group(1) if a else "nan", b.group(1) if b else "0"]
        f.write(f"{v},{label},{ops[0]},{ops[1]},{fmt(med.get(f'cost/{v}/lean'))},{fmt(med.get(f'cost/{v}/runtime'))}\n")
gp.append(f'set output "{res}/cost.svg"')
gp.append('set multiplot layout 1,2 title "fourbar: the cost of asking for more outputs"')
gp.append('unset logscale; set style data histograms; set style histogram clustered gap 1; set style fill solid 0.7 border -1; set yrange [0:*]; set format y "%g"; set key top left')
gp.append(f'set ylabel "generated operations"; set xlabel ""; plot "{cost}" using 3:xtic(2) title "EvalPhi", "" using 4 title "EvalCoefficients"')
gp.append(f'set ylabel "CPU time per configuration [ns]"; plot "{cost}" using 5:xtic(2) title "Newton + generated outputs", "" using 6 title "runtime MoveTo"')
gp.append('unset multiplot; set style data points; set logscale xy; set format y "10^{%L}"')

# --- the N-chain: every method against N (bench/chain has generation time and code size) ---
chains = sorted((int(m[5:]), m) for m in models if re.fullmatch(r"chain\d+", m))
if chains:
    meths = ["dyads", "monolithic", "newton_symbolic", "newton_numeric", "runtime", "ceres_analytic",
             "fd_h1e-5", "ode_rk4_newton10", "float_newton", "float_dyads"]
    chain = os.path.join(res, "chain_methods.csv")
    with open(chain, "w") as f:
        f.write(stamp + "\n")
        f.write("# N-chain (tools/make_chain.sh N), 360 configurations of a crank turn: median CPU ns per configuration\n")
        f.write("# (positions + K + L) and max error of positions / K / L against tests/reference/data/chain<N>.csv, per method\n")
        f.write("N," + ",".join(f"{x}_ns,{x}_pos,{x}_K,{x}_L" for x in meths) + "\n")
        for n, m in chains:
            errs = {}
            for r in csv.DictReader(l for l in open(os.path.join(res, f"{m}_tradeoff.csv")) if not l.startswith("#")):
                errs[r["method"]] = r
            f.write(str(n))
            for x in meths:
                r = errs.get(x, {})
                f.write("," + ",".join(r.get(c, "nan") for c in ("ns", "max_pos", "max_K", "max_L")))
            f.write("\n")
    gp.append(f'set output "{res}/chain_methods.svg"')
    gp.append('set terminal svg size 1200,450 dynamic enhanced font "sans,11" background "white"')
    gp.append('set multiplot layout 1,2 title "N four-bars in series: every method against N (' + stamp.split(";")[0][2:] + ')"')
    gp.append('set logscale xy; set xlabel "N (loops)"; set format y "10^{%L}"; set key top left font ",8"; set xtics (2, 4, 8, 16)')
    parts = [f'"{chain}" using 1:{2 + 4 * i} with linespoints pt 7 title "{x.replace("_", " ")}"' for i, x in enumerate(meths)]
    gp.append('set ylabel "CPU time per configuration [ns]"; set format y "%g"; plot ' + ", ".join(parts))
    parts = [f'"{chain}" using 1:(column({5 + 4 * i}) < 1e-17 ? 1e-17 : column({5 + 4 * i})) with linespoints pt 7 title "{x.replace("_", " ")}"' for i, x in enumerate(meths)]
    gp.append('set ylabel "max error of L (rel.)"; set format y "10^{%L}"; set yrange [1e-17:1]; set key bottom right; plot ' + ", ".join(parts))
    gp.append("unset multiplot; unset yrange; unset xtics; set xtics")

open(os.path.join(tmp, "plots.gp"), "w").write("\n".join(gp) + "\n")

# A short text summary for the console.
print(stamp)
for m in models:
    print(f"\n{m}: method, CPU ns/configuration, max error pos / K / L")
    for line in open(os.path.join(res, f"{m}_tradeoff.csv")):
        if line.startswith("#") or line.startswith("method"): continue
        p = line.strip().split(",")
        print(f"  {p[0]:<18} {float(p[1]):9.1f}   {p[2]:>9} {p[3]:>9} {p[4]:>9}")
print("\ncost of asking for more (fourbar):")
for line in open(cost):
    if not line.startswith("#"): print("  " + line.strip())
PY
gnuplot "$TMP/plots.gp"
echo "run.sh: figures and data in bench/accuracy/results/"
