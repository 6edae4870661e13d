#!/usr/bin/env python3
"""The tools' --design outputs (issue 27, through time) against central differences of the same
tools' own runs with one design parameter moved by +-h (--set):
 - simulate --design: every d<q>/d<p> and d<q>_dot/d<p> at every row (trajectory
   sensitivities) against two free simulations at a tight tolerance;
 - flywheel --design: the printed dT_mean/dp, d(dE)/dp, dI/dp and dI_fly/dp and the CSV's
   dT_req/d<p> columns against two flywheel sizings.
Every sensitivity column is described with its unit in the CSV's header; --design's usage
errors are one line, exit 2, no CSV.

Usage: tool_design_test.py OUT_DIR DESIGN_PRESS_SIMULATE DESIGN_PRESS_FLYWHEEL
"""
import csv
import os
import re
import subprocess
import sys

out_dir, simulate, flywheel = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out_dir, exist_ok=True)
# tests/design/models/design_press.yaml: design: {parameters: all}
defaults = {"a": 0.1, "b": 0.35, "e": 0.02, "m1": 2.0, "m2": 3.0, "m3": 8.0, "xH": 0.9, "c": 400.0,
            "k": 2000.0, "L0": 0.4, "g": 9.81}
failures = []


def read_csv(path):
    with open(path) as f:
        lines = f.read().splitlines()
    return [l for l in lines if l.startswith("#")], list(csv.DictReader(l for l in lines if not l.startswith("#")))


def check_described(comments, cols):
    for c in cols:
        if not any(l.startswith("# " + c + " [") and "per unit of" in l for l in comments):
            failures.append(f"column {c} is not described with its unit in the header")


def compare(what, got, fd, tol, stats):
    err = abs(got - fd) / max(1.0, abs(fd))
    stats[0] = max(stats[0], err)
    stats[1] += 1
    if not err <= tol:
        failures.append(f"{what} = {got!r}, central differences {fd!r}")


# ---- simulate --design ----
sim_common = ["--t-end", "0.5", "--dt", "0.05", "--qd0", "12", "--method", "dop853", "--no-steady"]


def run_simulate(name, *args):
    path = os.path.join(out_dir, name + ".csv")
    subprocess.run([simulate, *sim_common, "--rtol", "1e-13", "--atol", "1e-14", "--csv", path, *args],
                   check=True, stdout=subprocess.DEVNULL)
    return read_csv(path)


comments, base = run_simulate("sim_base", "--design")
design_cols = [c for c in base[0] if "/d" in c]
if sorted({c.split("/d")[-1] for c in design_cols}) != sorted(defaults):
    failures.append(f"simulate: design parameters {sorted({c.split('/d')[-1] for c in design_cols})}")
check_described(comments, design_cols)
sim_stats = [0.0, 0]
for p, v in defaults.items():
    # Richardson's extrapolation of central differences at h and h/2: the press's motion is
    # strongly nonlinear in its parameters (the damper stops and reverses the crank within the
    # run), so a plain central difference at h = 1e-5 is only good to ~1e-4 there.
    h = 1e-5 * max(1e-2, abs(v))
    runs = {}
    for key, delta in (("p", h), ("m", -h), ("p2", h / 2), ("m2", -h / 2)):
        runs[key] = run_simulate(f"sim_{key}_{p}", "--set", f"{p}={v + delta!r}")[1]
    for c in [c for c in design_cols if c.endswith("/d" + p)]:
        value_col = c[1:-len("/d" + p)]  # dtheta_crank/da -> theta_crank
        for k, row in enumerate(base):
            def diff(a, b, step):
                return (float(runs[a][k][value_col]) - float(runs[b][k][value_col])) / step
            fd = (4 * diff("p2", "m2", h) - diff("p", "m", 2 * h)) / 3
            compare(f"simulate row {k}: {c}", float(row[c]), fd, 1e-6, sim_stats)
print(f"simulate --design: worst relative difference {sim_stats[0]:.2e} over {sim_stats[1]} cells")
if sim_stats[1] < 200:
    failures.append(f"simulate: only {sim_stats[1]} cells compared")
for bad in (["--design", "--energy-projection"], ["--design", "--drive", "theta_crank=speed:1"]):
    r = subprocess.run([simulate, *sim_common, *bad, "--csv", os.path.join(out_dir, "bad.csv")],
                       capture_output=True, text=True)
    if r.returncode != 2 or len(r.stderr.strip().splitlines()) != 1 or "--design" not in r.stderr:
        failures.append(f"simulate {bad}: exit {r.returncode}, stderr {r.stderr!r} (expected one line, exit 2)")
    if os.path.exists(os.path.join(out_dir, "bad.csv")):
        failures.append(f"simulate {bad}: a CSV was written")

# ---- flywheel --design ----
fly_common = ["--rpm", "120", "--cs", "0.05", "--samples", "360", "--no-check"]


def run_flywheel(name, *args):
    path = os.path.join(out_dir, name + ".csv")
    out = subprocess.run([flywheel, *fly_common, "--csv", path, *args], check=True, capture_output=True,
                         text=True).stdout
    # The figures to full precision: the --design table's heading says them with 17 digits.
    m = re.search(r"design sensitivities of T_mean = (\S+) N m, dE = (\S+) J, I = (\S+) kg m\^2, "
                  r"I_fly = (\S+) kg m\^2", out)
    values = dict(zip(["T_mean", "dE", "I", "I_fly"], [float(x) for x in m.groups()]))
    return out, values, read_csv(path)


out, _, (comments, base) = run_flywheel("fly_base", "--design")
table = {}
for line in out.splitlines():
    parts = line.split()
    if len(parts) == 5 and parts[0] in defaults:
        table[parts[0]] = [float(x) for x in parts[1:]]
if sorted(table) != sorted(defaults):
    failures.append(f"flywheel: the printed design table has {sorted(table)}")
check_described(comments, [c for c in base[0] if "/d" in c])
fly_stats = [0.0, 0]
for p, v in defaults.items():
    h = 1e-5 * max(1e-2, abs(v))
    _, plus, (_, plus_rows) = run_flywheel(f"fly_plus_{p}", "--design", "--set", f"{p}={v + h!r}")
    _, minus, (_, minus_rows) = run_flywheel(f"fly_minus_{p}", "--design", "--set", f"{p}={v - h!r}")
    for i, name in enumerate(["T_mean", "dE", "I", "I_fly"]):
        fd = (plus[name] - minus[name]) / (2 * h)
        # the printed table has 9 significant digits
        compare(f"flywheel d{name}/d{p}", table.get(p, [float("nan")] * 4)[i], fd, 1e-6, fly_stats)
    for k, row in enumerate(base):
        fd = (float(plus_rows[k]["T_req"]) - float(minus_rows[k]["T_req"])) / (2 * h)
        compare(f"flywheel row {k}: dT_req/d{p}", float(row["dT_req/d" + p]), fd, 1e-6, fly_stats)
print(f"flywheel --design: worst relative difference {fly_stats[0]:.2e} over {fly_stats[1]} figures and cells")
for f in failures[:20]:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
