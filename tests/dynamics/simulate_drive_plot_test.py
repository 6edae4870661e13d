#!/usr/bin/env python3
"""A motion generator at constant crank speed (slider_crank_motor_simulate --drive
theta_crank=speed:W), end to end (issue 25: the dynamics plot shows what was asked).

Oracles, independent of the tool's arithmetic:
  * lambda, the motor torque the law needs, against the energy: at constant speed the equation
    of motion I(q) q'' + 1/2 I'(q) q'^2 = Q + lambda reduces to lambda = dT/dq - Q, with dT/dq
    the central difference of the kinetic-energy column T over the rows (T and lambda come from
    different generated functions; the difference's error is O(h^2) in the step h = W dt);
  * the bearing loads F_<joint>_mag are |(F_<joint>_x, F_<joint>_y)| in every row, for every
    revolute joint with reaction columns (the columns the README promises in this mode);
  * the summary's lambda range and largest bearing load are the CSV's;
  * plot_dynamics.gnuplot draws the driven run against the accumulated crank angle with the
    lambda panel, and a free run against t with the Q panel (SVG text checked; also rendered
    to PNG when gnuplot has pngcairo).
usage: simulate_drive_plot_test.py <slider_crank_motor_simulate> <plot_dynamics.gnuplot> <scratch dir>
"""
import csv
import math
import os
import re
import shutil
import subprocess
import sys

tool, plot, scratch = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(scratch, exist_ok=True)
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def read(path):
    with open(path) as f:
        return [{k: (float(v) if v != "" else math.nan) for k, v in r.items()}
                for r in csv.DictReader(line for line in f if not line.startswith("#"))]


W, dt = 10.0, 0.0005
driven = os.path.join(scratch, "driven.csv")
p = subprocess.run([tool, "--drive", "theta_crank=speed:%g" % W, "--t-end", "1.5", "--dt", str(dt),
                    "--rtol", "1e-11", "--atol", "1e-13", "--csv", driven], capture_output=True, text=True)
check(p.returncode == 0, "driven run: exit %d, stderr %s" % (p.returncode, p.stderr))
rows = read(driven) if os.path.exists(driven) else []
check(len(rows) > 100, "driven run: %d rows" % len(rows))

# lambda = dT/dq - Q at constant speed.
worst, scale = 0.0, 0.0
for a, b, c in zip(rows, rows[1:], rows[2:]):
    dT = (c["T"] - a["T"]) / (c["theta_crank"] - a["theta_crank"])
    worst = max(worst, abs(b["lambda_theta_crank"] - (dT - b["Q_theta_crank"])))
    scale = max(scale, abs(b["lambda_theta_crank"]))
check(scale > 1, "lambda is about zero (max %.3g N m): the test would show nothing" % scale)
check(worst < 1e-4 * scale, "lambda differs from dT/dq - Q by %.3g N m (max |lambda| %.3g)" % (worst, scale))

# |F| columns of every revolute joint.
names = [k[:-4] for k in rows[0].keys() if k.startswith("F_") and k.endswith("_mag")] if rows else []
check(len(names) >= 3, "driven run: bearing-load columns %s, expected F_O_mag, F_B_mag, F_C_mag" % names)
largest, largest_joint = 0.0, ""
for r in rows:
    for n in names:
        m = math.hypot(r[n + "_x"], r[n + "_y"])
        check(abs(r[n + "_mag"] - m) <= 1e-12 * (1 + m), "%s_mag = %r, |(x, y)| = %r" % (n, r[n + "_mag"], m))
        if m > largest:
            largest, largest_joint = m, n[2:]
lam = [r["lambda_theta_crank"] for r in rows]
m = re.search(r"lambda_theta_crank from (\S+) to (\S+) N m", p.stdout)
check(m and abs(float(m.group(1)) - min(lam)) <= 1e-5 * scale and abs(float(m.group(2)) - max(lam)) <= 1e-5 * scale,
      "summary's lambda range %s, CSV's [%.6g, %.6g]" % (m.groups() if m else None, min(lam), max(lam)))
m = re.search(r"largest bearing load: (\S+) N at joint (\S+)", p.stdout)
check(m and abs(float(m.group(1)) - largest) <= 1e-5 * largest and m.group(2) == largest_joint,
      "summary's largest bearing load %s, CSV's %.6g N at %s" % (m.groups() if m else None, largest, largest_joint))

free = os.path.join(scratch, "free.csv")
p = subprocess.run([tool, "--t-end", "0.5", "--dt", "0.005", "--csv", free, "--quiet"], capture_output=True, text=True)
check(p.returncode == 0, "free run: exit %d, stderr %s" % (p.returncode, p.stderr))

if shutil.which("gnuplot"):
    for name, expect, absent in (("driven", ["lambda_theta_crank", "theta_crank (deg, accumulated)", "F_O_mag",
                                             "E - W_nc - W_act"], ["Q_theta_crank"]),
                                 ("free", ["Q_theta_crank", "t (s)", "F_O_mag", "E - W_nc"], ["lambda_"])):
        svg = os.path.join(scratch, name + ".svg")
        g = subprocess.run(["gnuplot", "-e", "csv='%s'; svg='%s'" % (os.path.join(scratch, name + ".csv"), svg), plot],
                           capture_output=True, text=True)
        check(g.returncode == 0 and os.path.exists(svg), "%s: gnuplot failed: %s" % (name, g.stderr))
        text = open(svg).read() if os.path.exists(svg) else ""
        for e in expect:
            check(e in text, "%s plot: no %r in the SVG" % (name, e))
        for a in absent:
            check(a not in text, "%s plot: %r should not be drawn" % (name, a))
        png = os.path.join(scratch, name + ".png")
        g = subprocess.run(["gnuplot", "-e", "csv='%s'; png='%s'" % (os.path.join(scratch, name + ".csv"), png), plot],
                           capture_output=True, text=True)
        check(g.returncode == 0 and os.path.getsize(png) > 10000, "%s: PNG not rendered: %s" % (name, g.stderr))
else:
    print("gnuplot not found: the plots are not checked")

print("max |lambda - (dT/dq - Q)| = %.3g N m of max |lambda| %.3g; %d failures" % (worst, scale, len(failures)))
sys.exit(1 if failures else 0)
