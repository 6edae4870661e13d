#!/usr/bin/env python3
"""The simulate tool's --design columns (issue 27: trajectory sensitivities) against central
differences of the same tool's free simulations with one design parameter moved by +-h (--set)
at a tight tolerance: every d<q>/d<p> and d<q>_dot/d<p> at every row. Every sensitivity column
is described with its unit in the CSV's header; the usage errors of --design are one line,
exit 2.

Usage: simulate_design_test.py OUT_DIR DESIGN_FOURBAR_MASSIVE_SIMULATE
"""
import csv
import os
import subprocess
import sys

out_dir, tool = sys.argv[1], sys.argv[2]
os.makedirs(out_dir, exist_ok=True)
common = ["--t-end", "1.5", "--dt", "0.05", "--qd0", "1.5", "--method", "dop853", "--no-steady"]


def run(name, *args):
    path = os.path.join(out_dir, name + ".csv")
    subprocess.run([tool, *common, "--rtol", "1e-13", "--atol", "1e-14", "--csv", path, *args],
                   check=True, stdout=subprocess.DEVNULL)
    with open(path) as f:
        lines = f.read().splitlines()
    comments = [l for l in lines if l.startswith("#")]
    rows = list(csv.DictReader(l for l in lines if not l.startswith("#")))
    return comments, rows


failures = []
comments, base = run("base", "--design")
design_cols = [c for c in base[0] if "/d" in c]
params = sorted({c.split("/d")[-1] for c in design_cols})
# tests/design/models/design_fourbar_massive.yaml: design: {parameters: all}
defaults = {"a": 1.0, "b": 3.5, "c": 3.0, "d": 4.0, "rho": 2.0, "g": 9.81}
if sorted(defaults) != params:
    failures.append(f"design parameters in the CSV {params}, expected {sorted(defaults)}")
if len(design_cols) != 2 * len(defaults):
    failures.append(f"{len(design_cols)} sensitivity columns, expected {2 * len(defaults)}")
for c in design_cols:
    if not any(l.startswith("# " + c + " [") and "per unit of" in l for l in comments):
        failures.append(f"column {c} is not described with its unit in the header")
worst = 0.0
checked = 0
for p, v in defaults.items():
    h = 1e-5 * max(1.0, abs(v))
    _, plus = run(f"plus_{p}", "--set", f"{p}={v + h!r}")
    _, minus = run(f"minus_{p}", "--set", f"{p}={v - h!r}")
    if len(plus) != len(base) or len(minus) != len(base):
        failures.append(f"{p}: {len(plus)} and {len(minus)} rows against {len(base)}")
        continue
    for c in [c for c in design_cols if c.endswith("/d" + p)]:
        value_col = c[1:-len("/d" + p)]  # dtheta_crank/da -> theta_crank
        for k, row in enumerate(base):
            got = float(row[c])
            fd = (float(plus[k][value_col]) - float(minus[k][value_col])) / (2 * h)
            err = abs(got - fd) / max(1.0, abs(fd))
            worst = max(worst, err)
            checked += 1
            if not err <= 1e-6:
                failures.append(f"row {k}: {c} = {got!r}, differences of {value_col}: {fd!r}")
print(f"worst relative difference {worst:.2e} over {checked} cells")
if checked < 300:
    failures.append(f"only {checked} cells compared")
for bad in (["--design", "--energy-projection"], ["--design", "--drive", "theta_crank=speed:1"]):
    r = subprocess.run([tool, *common, *bad, "--csv", os.path.join(out_dir, "bad.csv")],
                       capture_output=True, text=True)
    if r.returncode != 2 or len(r.stderr.strip().splitlines()) != 1 or "--design" not in r.stderr:
        failures.append(f"{bad}: exit {r.returncode}, stderr {r.stderr!r} (expected one line, exit 2)")
    if os.path.exists(os.path.join(out_dir, "bad.csv")):
        failures.append(f"{bad}: a CSV was written")
for f in failures[:20]:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
