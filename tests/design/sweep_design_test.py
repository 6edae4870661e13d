#!/usr/bin/env python3
"""The sweep's --design columns (issue 27) against central differences of the same tool's
sweeps with one design parameter moved by +-h (--set): an oracle that is the values code
alone, solved again at each parameter value. Also: every d<output>/d<p> column is described
in the CSV's header with its unit, and a model without a design section is refused with
exit 2 and one line.

Usage: sweep_design_test.py OUT_DIR FOURBAR_SWEEP NO_DESIGN_SWEEP
"""
import csv
import math
import os
import subprocess
import sys

out_dir, sweep, no_design = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out_dir, exist_ok=True)


def run(name, *args):
    path = os.path.join(out_dir, name + ".csv")
    subprocess.run([sweep, "--steps", "24", "--csv", path, *args], check=True, stdout=subprocess.DEVNULL)
    with open(path) as f:
        lines = f.read().splitlines()
    comments = [l for l in lines if l.startswith("#")]
    rows = list(csv.DictReader(l for l in lines if not l.startswith("#")))
    return comments, rows


failures = []
comments, base = run("base", "--design")
design_cols = [c for c in base[0] if c.startswith("d") and "/d" in c]
if not design_cols:
    failures.append("no d<output>/d<p> columns")
for c in design_cols:
    if not any(l.startswith("# " + c + " [") and "per unit of" in l for l in comments):
        failures.append(f"column {c} is not described with its unit in the header")

defaults = {"a": 1.0, "b": 3.5, "c": 3.0, "d": 4.0, "xi": 1.5, "eta": 1.0}  # models/fourbar.yaml
outputs = ["theta_coupler", "theta_rocker", "coupler.P.x", "coupler.P.y", "mu_C"]
worst = 0.0
for p, v in defaults.items():
    h = 1e-5 * max(1.0, abs(v))
    _, plus = run(f"plus_{p}", "--set", f"{p}={v + h!r}")
    _, minus = run(f"minus_{p}", "--set", f"{p}={v - h!r}")
    for k, row in enumerate(base):
        for o in outputs:
            got = float(row[f"d{o}/d{p}"])
            fd = (float(plus[k][o]) - float(minus[k][o])) / (2 * h)
            err = abs(got - fd) / max(1.0, abs(fd))
            worst = max(worst, err)
            # central difference: h^2 f'''/6 ~ 1e-10 plus rounding 1e-16/h ~ 1e-11
            if not err <= 1e-7:
                failures.append(f"row {k}: d{o}/d{p} = {got!r}, differences {fd!r}")
print(f"worst relative difference {worst:.2e} over {len(base)} rows x {len(defaults)} parameters")

r = subprocess.run([no_design, "--design"], capture_output=True, text=True)
if r.returncode != 2 or len(r.stderr.strip().splitlines()) != 1 or "design" not in r.stderr:
    failures.append(f"a model without design: exit {r.returncode}, stderr {r.stderr!r}")

for f in failures[:20]:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
