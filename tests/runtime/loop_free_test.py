#!/usr/bin/env python3
"""A model without a closed loop in every analysis it has (issue 25).

tests/runtime/models/pendulum_spring.yaml: one bar OA = l pinned at O, its mass m at c along
the bar (Jc about the centre), gravity g along -y, a torsional spring k at O (free angle
theta0), a force Fy along y at A. kNc = kNphi = 0: the generated model has no Phi rows and
every coordinate is an input. Its sweep, statics and simulate commands run, and their numbers
agree with closed forms written here from the mechanics, not from the code:
  sweep:    A = l (cos t, sin t), v_A = l qd (-sin t, cos t), a_A = -l qd^2 (cos t, sin t);
  statics:  drive = dV/dt - (work of Fy) = (m g c - Fy l) cos t + k (t - theta0); the pin
            carries the weight less the load, F_O = (0, m g - Fy); V = m g c sin t +
            k (t - theta0)^2 / 2; stiffness d(drive)/dt = -(m g c - Fy l) sin t + k; the one
            equilibrium in [-pi, pi] where drive = 0;
  simulate: small swings about that equilibrium t_e last 2 pi sqrt(I_O / k_e) with I_O =
            Jc + m c^2 and k_e the stiffness there (the linearised equation of motion);
            T + V - W_nc stays constant; T = I_O qd^2 / 2.
Usage: loop_free_test.py MECHGEN_VIEW PENDULUM_SPRING.so
(the model's shared object; its sweep, statics and simulate commands through mechgen_view,
the per-model tools' output: tests/runtime's *_view_test.sh)
"""
import csv
import math
import os
import subprocess
import sys
import tempfile

l, c, m, Jc, g, k, theta0, Fy = 0.8, 0.5, 2.0, 0.03, 9.81, 3.0, 0.25, 4.0
I_O = Jc + m * c * c
A = m * g * c - Fy * l  # gravity less the load, as a torque coefficient of cos t

failures = 0


def check(ok, what):
    global failures
    if not ok:
        failures += 1
        print("FAIL: " + what)


def close(a, b, tol, what):
    check(abs(a - b) <= tol * max(1.0, abs(b)), "%s: %.17g, expected %.17g" % (what, a, b))


def run(args):
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       universal_newlines=True)
    if p.returncode != 0:
        print("FAIL: %s: exit %d\n%s%s" % (" ".join(args), p.returncode, p.stdout, p.stderr))
        sys.exit(1)
    return p.stdout


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def drive(t):
    return A * math.cos(t) + k * (t - theta0)


def stiffness(t):
    return -A * math.sin(t) + k


def main():
    view, model = sys.argv[1:3]
    sweep, statics, simulate = ([view, command, model] for command in ("sweep", "statics", "simulate"))
    tmp = tempfile.mkdtemp()

    # Sweep: positions, velocities, accelerations of the tip in closed form.
    out = os.path.join(tmp, "sweep.csv")
    svg = os.path.join(tmp, "sweep.svg")
    qd = 1.7
    text = run(sweep + ["--steps", "72", "--qd", str(qd), "--csv", out, "--svg", svg])
    check("no closed loop" in text, "sweep: the loop-free model is not said to be one:\n" + text)
    r = rows(out)
    check(len(r) == 73, "sweep: %d rows" % len(r))
    for row in r:
        t = float(row["theta_bar"])
        check(row["status"] == "converged", "sweep: status %s" % row["status"])
        close(float(row["bar.A.x"]), l * math.cos(t), 1e-14, "sweep A.x")
        close(float(row["bar.A.y"]), l * math.sin(t), 1e-14, "sweep A.y")
        close(float(row["bar.A.vx"]), -l * qd * math.sin(t), 1e-14, "sweep A.vx")
        close(float(row["bar.A.vy"]), l * qd * math.cos(t), 1e-14, "sweep A.vy")
        close(float(row["bar.A.ax"]), -l * qd * qd * math.cos(t), 1e-14, "sweep A.ax")
        close(float(row["bar.A.ay"]), -l * qd * qd * math.sin(t), 1e-14, "sweep A.ay")
    check(os.path.getsize(svg) > 0 and "<svg" in open(svg).read(), "sweep: no SVG")

    # Statics: driving torque, pin reaction, potential, stiffness, the equilibrium.
    out = os.path.join(tmp, "statics.csv")
    text = run(statics + ["--steps", "90", "--csv", out, "--svg", os.path.join(tmp, "st.svg"),
                "--equilibria", "--dead-zones"])
    r = rows(out)
    check(len(r) == 91, "statics: %d rows" % len(r))
    for row in r:
        t = float(row["theta_bar"])
        check(row["status"] == "converged", "statics: status %s" % row["status"])
        close(float(row["drive_theta_bar"]), drive(t), 1e-12, "statics drive at %g" % t)
        close(float(row["F_O_x"]), 0.0, 1e-12, "statics F_O_x")
        close(float(row["F_O_y"]), m * g - Fy, 1e-12, "statics F_O_y")
        close(float(row["V"]), m * g * c * math.sin(t) + 0.5 * k * (t - theta0) ** 2, 1e-12,
              "statics V")
        close(float(row["stiffness"]), stiffness(t), 1e-12, "statics stiffness")
    # The equilibrium, by Newton on the closed form from t = -1.
    t_e = -1.0
    for _ in range(50):
        t_e -= drive(t_e) / stiffness(t_e)
    line = [s for s in text.splitlines() if s.strip().startswith("theta_bar =")]
    check(len(line) == 1, "statics: one equilibrium expected:\n" + text)
    if line:
        found = float(line[0].split("=")[1].split("deg")[0]) * math.pi / 180
        close(found, t_e, 1e-5, "statics equilibrium (deg printed to 4 decimals)")
        check("stable" in line[0] and "unstable" not in line[0], "equilibrium not stable: " + line[0])

    # Simulate: the small-swing period about t_e and the energy balance.
    out = os.path.join(tmp, "sim.csv")
    amplitude = 1e-3
    period = 2 * math.pi * math.sqrt(I_O / stiffness(t_e))
    run(simulate + ["--t-end", str(4.2 * period), "--dt", "1e-4", "--no-steady", "--quiet",
         "--rtol", "1e-11", "--atol", "1e-13", "--q0", repr(t_e + amplitude), "--csv", out])
    r = rows(out)
    t = [float(x["t"]) for x in r]
    y = [float(x["theta_bar"]) - t_e for x in r]
    # Upward zero crossings of y, linearly interpolated.
    ups = [t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
           for i in range(len(y) - 1) if y[i] < 0 <= y[i + 1]]
    check(len(ups) >= 4, "simulate: %d upward crossings" % len(ups))
    if len(ups) >= 2:
        measured = (ups[-1] - ups[0]) / (len(ups) - 1)
        # Nonlinearity at 1e-3 rad: relative ~1e-6; interpolation at dt = 1e-4: smaller.
        close(measured, period, 1e-5, "simulate small-swing period (s)")
    E0 = float(r[0]["E"]) - float(r[0]["W_nc"])
    drift = max(abs(float(x["E"]) - float(x["W_nc"]) - E0) for x in r)
    check(drift <= 1e-8, "simulate: E - W_nc drifts by %g J" % drift)
    for x in r[:: max(1, len(r) // 50)]:
        close(float(x["T"]), 0.5 * I_O * float(x["theta_bar_dot"]) ** 2, 1e-12, "simulate T")

    # A larger swing with the spring and load: energy balance against the closed-form V and
    # the load's work -Fy l (sin t - sin t0) (W_nc: the work of the non-conservative forces).
    run(simulate + ["--t-end", "2", "--no-steady", "--quiet", "--q0", "1.2", "--qd0", "-3",
         "--rtol", "1e-11", "--atol", "1e-13", "--csv", out])
    r = rows(out)
    for x in r[:: max(1, len(r) // 50)]:
        tt = float(x["theta_bar"])
        V = m * g * c * math.sin(tt) + 0.5 * k * (tt - theta0) ** 2
        close(float(x["V"]), V, 1e-12, "simulate V")
        close(float(x["W_nc"]), Fy * l * (math.sin(tt) - math.sin(1.2)), 1e-8,
              "simulate W_nc (integrated at rtol 1e-11)")
    drift = max(abs(float(x["E"]) - float(x["W_nc"]) - float(r[0]["E"])) for x in r)
    check(drift <= 1e-6, "simulate: large swing E - W_nc drifts by %g J" % drift)

    if failures:
        print("%d failure(s)" % failures)
        return 1
    print("ok: sweep, statics and simulate of the loop-free pendulum agree with the closed forms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
