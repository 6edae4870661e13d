#!/usr/bin/env python3
"""fivebar_robot_simulate with --drive (motion generators), end to end.

Oracles, independent of the tool's own arithmetic:
  * the driven inputs' q, q_dot, q_ddot columns equal the laws written out here (3-4-5,
    cycloidal, constant speed; a table's knots are interpolated exactly);
  * held still (speed:0) from rest, the motors' torques are the static holding torques:
    lambda = dV/dq, the central difference of the potential column V between runs at
    q0 +- h (virtual work; V and lambda come from different generated functions);
  * with every input driven, the balance E - W_nc - W_act stays at its initial value;
  * bad --drive options exit with 2 and say what is wrong; a run into a singular configuration
    exits with 1 and gives 1/cond(Phi_phi).
usage: simulate_drive_test.py <fivebar_robot_simulate> <scratch dir>
"""
import csv
import math
import os
import subprocess
import sys

tool, scratch = sys.argv[1], sys.argv[2]
os.makedirs(scratch, exist_ok=True)
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def run(args, name):
    path = os.path.join(scratch, name + ".csv")
    if os.path.exists(path):
        os.remove(path)
    p = subprocess.run([tool] + args + ["--csv", path, "--quiet"], capture_output=True, text=True)
    rows = []
    if os.path.exists(path):
        with open(path) as f:
            rows = [{k: (float(v) if v != "" else math.nan) for k, v in r.items()}
                    for r in csv.DictReader(line for line in f if not line.startswith("#"))]
    return p, rows


Q1_0, Q2_0 = 135 * math.pi / 180, 45 * math.pi / 180  # the model's assembly inputs


def poly345(q0, q1, t0, t1, t):
    if t <= t0:
        return q0, 0.0, 0.0
    if t >= t1:
        return q1, 0.0, 0.0
    T, H = t1 - t0, q1 - q0
    u = (t - t0) / T
    return (q0 + H * (10 * u**3 - 15 * u**4 + 6 * u**5), H / T * (30 * u**2 - 60 * u**3 + 30 * u**4),
            H / T**2 * (60 * u - 180 * u**2 + 120 * u**3))


def cycloidal(q0, q1, t0, t1, t):
    if t <= t0:
        return q0, 0.0, 0.0
    if t >= t1:
        return q1, 0.0, 0.0
    T, H = t1 - t0, q1 - q0
    u = (t - t0) / T
    w = 2 * math.pi
    return (q0 + H * (u - math.sin(w * u) / w), H / T * (1 - math.cos(w * u)),
            H / T**2 * w * math.sin(w * u))


# 1. Both motors driven (inverse dynamics): the columns follow the laws; the balance holds.
p, rows = run(["--rtol", "1e-10", "--atol", "1e-12", "--drive", "theta_prox1=move:120deg:0.1:0.6", "--drive",
               "theta_prox2=cycloidal:60deg:0:0.5", "--t-end", "0.8", "--dt", "0.01"], "both")
check(p.returncode == 0, "both driven: exit %d, stderr %s" % (p.returncode, p.stderr))
check(len(rows) == 81, "both driven: %d rows, expected 81" % len(rows))
worst = 0.0
for r in rows:
    t = r["t"]
    for name, law in (("theta_prox1", poly345(Q1_0, 120 * math.pi / 180, 0.1, 0.6, t)),
                      ("theta_prox2", cycloidal(Q2_0, 60 * math.pi / 180, 0.0, 0.5, t))):
        for column, value in zip((name, name + "_dot", name + "_ddot"), law):
            worst = max(worst, abs(r[column] - value) / (1 + abs(value)))
check(worst < 1e-9, "both driven: the driven columns differ from the laws by %.3g" % worst)
balance = max(abs(r["balance"] - rows[0]["balance"]) for r in rows) if rows else math.inf
check(balance < 1e-7, "both driven: E - W_nc - W_act drifts by %.3g J" % balance)
check(all(math.isfinite(r["lambda_theta_prox1"]) and math.isfinite(r["lambda_theta_prox2"])
          for r in rows), "both driven: a lambda is not finite")

# 2. Held still from rest: lambda = dV/dq (central differences of V over --q0).
h = 1e-5
_, rest = run(["--drive", "theta_prox1=speed:0", "--drive", "theta_prox2=speed:0",
               "--t-end", "0.01", "--dt", "0.01"], "rest")
for i, name in enumerate(("theta_prox1", "theta_prox2")):
    V = []
    for sign in (+1, -1):
        q0 = [Q1_0, Q2_0]
        q0[i] += sign * h
        _, r = run(["--q0", "%.17g,%.17g" % tuple(q0), "--drive", "theta_prox1=speed:0",
                    "--drive", "theta_prox2=speed:0", "--t-end", "0.01", "--dt", "0.01"],
                   "rest_%s_%d" % (name, sign))
        V.append(r[0]["V"] if r else math.nan)
    dV = (V[0] - V[1]) / (2 * h)
    lam = rest[0]["lambda_" + name] if rest else math.nan
    check(abs(lam - dV) < 1e-6 * (1 + abs(dV)),
          "held still: lambda_%s = %.12g, dV/dq = %.12g" % (name, lam, dV))
    # Held still, nothing moves: lambda stays the holding torque over the run.
    check(rest and abs(rest[-1]["lambda_" + name] - lam) < 1e-9,
          "held still: lambda_%s changes over the run" % name)

# 3. A table law: the knots are interpolated exactly; outside, the end value holds (clamped).
table = os.path.join(scratch, "law_table.csv")
knots = [(0.0, Q1_0), (0.2, Q1_0 + 0.1), (0.4, Q1_0 + 0.25), (0.6, Q1_0 + 0.2)]
with open(table, "w") as f:
    f.write("t,q\n")
    for t, q in knots:
        f.write("%.17g,%.17g\n" % (t, q))
p, rows = run(["--drive", "theta_prox1=table:" + table, "--drive", "theta_prox2=speed:0",
               "--t-end", "0.8", "--dt", "0.05"], "table")
check(p.returncode == 0, "table: exit %d, stderr %s" % (p.returncode, p.stderr))
for t, q in knots + [(0.7, knots[-1][1]), (0.8, knots[-1][1])]:
    match = [r for r in rows if abs(r["t"] - t) < 1e-12]
    check(match and abs(match[0]["theta_prox1"] - q) < 1e-12,
          "table: theta_prox1(%g) = %s, expected %.12g" %
          (t, match[0]["theta_prox1"] if match else "no row", q))

# 4. Bad options: exit 2 with the reason.
for args, expect in (
        (["--drive", "theta_nope=speed:1"], "no input 'theta_nope'"),
        (["--drive", "theta_prox1=speed:1", "--drive", "theta_prox1=speed:2"], "driven twice"),
        (["--drive", "theta_prox1=warp:1"], "--drive: bad value"),
        (["--drive", "theta_prox1=move:1:0.5:0.2"], "--drive: bad value"),
        (["--drive", "theta_prox1=table:" + os.path.join(scratch, "missing.csv")], "cannot read")):
    p, _ = run(args, "bad")
    check(p.returncode == 2 and expect in p.stderr and p.stderr.count("\n") == 1
          and p.stderr.startswith("fivebar_robot_simulate: error: "),
          "%s: exit %d, stderr %r (expected exit 2 and one line with %r)"
          % (args, p.returncode, p.stderr, expect))
    check(not os.path.exists(os.path.join(scratch, "bad.csv")), "%s: a CSV was written" % args)

# 5. One motor at speed, the other free: the free arm falls into a singular configuration;
#    the run stops there (exit 1) with the figure, not through it.
p, rows = run(["--drive", "theta_prox1=speed:1", "--t-end", "1", "--dt", "0.01"], "singular")
check(p.returncode == 1 and "dead_point" in p.stderr and "1/cond(Phi_phi)" in p.stderr,
      "singular: exit %d, stderr %r" % (p.returncode, p.stderr))
check(rows and rows[-1]["rcond"] < 1e-3, "singular: the last row's rcond is not small")

# 6. Both motors driven into the stretched configuration: the run stops there (exit 1); the
#    motors' torques there grow like 1/sigma_min(Phi_phi) (they were printed as 2.5e19 N m): the
#    last row's lambda cells are empty (withheld), every row before has them finite, and the
#    summary says 'withheld' instead of a number.
p, rows = run(["--drive", "theta_prox1=speed:1", "--drive", "theta_prox2=speed:-1", "--t-end", "2",
               "--dt", "0.001"], "stretched")
check(p.returncode == 1 and "dead_point" in p.stderr, "stretched: exit %d, stderr %r" % (p.returncode, p.stderr))
check(len(rows) > 10 and all(math.isnan(rows[-1][k]) for k in ("lambda_theta_prox1", "lambda_theta_prox2")),
      "stretched: the last row's torques are not withheld: %r" % (rows[-1] if rows else None))
check(all(math.isfinite(r[k]) and abs(r[k]) < 1e6 for r in rows[:-1]
          for k in ("lambda_theta_prox1", "lambda_theta_prox2")),
      "stretched: a row before the stop has a torque that is not finite or is huge")
q = subprocess.run([tool, "--drive", "theta_prox1=speed:1", "--drive", "theta_prox2=speed:-1",
                    "--t-end", "2", "--csv", os.path.join(scratch, "stretched2.csv")],
                   capture_output=True, text=True)
check(q.returncode == 1 and "lambda_theta_prox1 withheld" in q.stdout and "e+19" not in q.stdout,
      "stretched: the summary does not withhold the torques: %r" % q.stdout)

print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
