#!/usr/bin/env python3
"""The engine tool's flywheel --design (issue 27: the cycle quantities of the engine analysis)
against central differences of the same tool's runs with one design parameter moved by +-h
(--set): d/dp of the mean torque, the energy loop's dE, the required inertia I and the flywheel
J_fly, the pressure trace held (an indicator diagram, --table: here the tool's own parametric
cycle written out at 0.25 deg). Also: --design without --table, or on another subcommand, is a
usage error of one line (exit 2).

Usage: engine_design_test.py OUT_DIR ENGINE_SINGLE_ENGINE
"""
import csv
import os
import re
import subprocess
import sys

out_dir, tool = sys.argv[1], os.path.abspath(sys.argv[2])
os.makedirs(out_dir, exist_ok=True)
failures = []
cycle_csv = os.path.join(out_dir, "cycle.csv")
subprocess.run([tool, "cycle", "--samples", "2880", "--csv", cycle_csv], check=True, stdout=subprocess.DEVNULL)
table = os.path.join(out_dir, "table.csv")
with open(cycle_csv) as f:
    rows = list(csv.DictReader(l for l in f if not l.startswith("#")))
with open(table, "w") as f:
    f.write("angle_deg,p_gauge_Pa\n")
    for r in rows:
        if float(r["theta_deg"]) < 720:
            f.write(f"{r['theta_deg']},{r['p_1']}\n")
# models/engine_single.yaml's design section and defaults
defaults = {"r": 0.043, "l": 0.145, "e": 0.0, "m_rod": 0.55, "l_G": 0.038, "J_rod": 0.0018, "m_pis": 0.45}
heading = re.compile(r"design sensitivities \(the pressure trace held\) of T_mean = (\S+) N m, dE = (\S+) J, "
                     r"I = (\S+) kg m\^2, J_fly = (\S+) kg m\^2")


def run(*args):
    out = subprocess.run([tool, "flywheel", "--design", "--table", table, "--samples", "720",
                          "--loop", os.path.join(out_dir, "loop.csv"), "--sweep", os.path.join(out_dir, "sweep.csv"),
                          "--wittenbauer", os.path.join(out_dir, "witt.csv"), *args],
                         capture_output=True, text=True).stdout
    # (the design block comes before the tool's simulated checks, whose shooting may miss its
    # 1e-9 periodicity on a piecewise-linear indicator diagram: their exit status is not this test's)
    figures = [float(x) for x in heading.search(out).groups()]
    table_rows = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 5 and parts[0] in defaults:
            table_rows[parts[0]] = [float(x) for x in parts[1:]]
    return figures, table_rows


_, derivatives = run()
if sorted(derivatives) != sorted(defaults):
    failures.append(f"the design table lists {sorted(derivatives)}")
worst, checked = 0.0, 0
for p, v in defaults.items():
    h = 1e-5 * max(0.01, abs(v))
    plus, _ = run("--set", f"{p}={v + h!r}")
    minus, _ = run("--set", f"{p}={v - h!r}")
    for i, name in enumerate(["T_mean", "dE", "I", "J_fly"]):
        fd = (plus[i] - minus[i]) / (2 * h)
        got = derivatives.get(p, [float("nan")] * 4)[i]
        err = abs(got - fd) / max(1.0, abs(fd))
        worst = max(worst, err)
        checked += 1
        if not err <= 1e-6:  # the printed table has 9 significant digits
            failures.append(f"d{name}/d{p} = {got!r}, central differences {fd!r}")
print(f"engine flywheel --design: worst relative difference {worst:.2e} over {checked} figures")
for bad in (["flywheel", "--design"], ["cycle", "--design", "--table", table]):
    r = subprocess.run([tool, *bad], capture_output=True, text=True, cwd=out_dir)
    if r.returncode != 2 or len(r.stderr.strip().splitlines()) != 1 or "--design" not in r.stderr:
        failures.append(f"{bad}: exit {r.returncode}, stderr {r.stderr!r} (expected one line, exit 2)")
for f in failures[:20]:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
