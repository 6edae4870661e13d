#!/usr/bin/env python3
"""The statics tool's --design columns (issue 27) against central differences of the same
tool's statics sweeps with one design parameter moved by +-h (--set): the driving torque's,
every reaction's and V's derivatives without friction. Every d<column>/d<p> is described with
its unit in the CSV's header.

Usage: statics_design_test.py OUT_DIR FOURBAR_LOADED_STATICS
"""
import csv
import os
import subprocess
import sys

out_dir, tool = sys.argv[1], sys.argv[2]
os.makedirs(out_dir, exist_ok=True)


def run(name, *args):
    path = os.path.join(out_dir, name + ".csv")
    subprocess.run([tool, "--steps", "24", "--csv", path, *args], check=True, stdout=subprocess.DEVNULL)
    with open(path) as f:
        lines = f.read().splitlines()
    comments = [l for l in lines if l.startswith("#")]
    rows = list(csv.DictReader(l for l in lines if not l.startswith("#")))
    return comments, rows


failures = []
comments, base = run("base", "--design")
design_cols = [c for c in base[0] if "/d" in c]
params = sorted({c.split("/d")[-1] for c in design_cols})
# models/fourbar_loaded.yaml's design section and defaults
defaults = {"a": 1.0, "b": 3.5, "c": 3.0, "d": 4.0, "xi": 1.5, "eta": 1.0, "k": 40.0, "F0": 5.0}
if sorted(defaults) != params:
    failures.append(f"design parameters in the CSV {params}, expected {sorted(defaults)}")
for c in design_cols:
    if not any(l.startswith("# " + c + " [") and "per unit of" in l for l in comments):
        failures.append(f"column {c} is not described with its unit in the header")
worst = 0.0
checked = 0
for p, v in defaults.items():
    h = 1e-5 * max(1.0, abs(v))
    _, plus = run(f"plus_{p}", "--set", f"{p}={v + h!r}")
    _, minus = run(f"minus_{p}", "--set", f"{p}={v - h!r}")
    for c in [c for c in design_cols if c.endswith("/d" + p)]:
        value_col = c[1:-len("/d" + p)]  # ddrive_x/dp -> drive_x, dF_A_x/dp -> F_A_x, dV/dp -> V
        for k, row in enumerate(base):
            if row[c] == "" or plus[k][value_col] == "" or minus[k][value_col] == "":
                continue
            got = float(row[c])
            fd = (float(plus[k][value_col]) - float(minus[k][value_col])) / (2 * h)
            err = abs(got - fd) / max(1.0, abs(fd))
            worst = max(worst, err)
            checked += 1
            if not err <= 1e-6:
                failures.append(f"row {k}: {c} = {got!r}, differences of {value_col}: {fd!r}")
print(f"worst relative difference {worst:.2e} over {checked} cells")
if checked < 1000:
    failures.append(f"only {checked} cells compared")
for f in failures[:20]:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
