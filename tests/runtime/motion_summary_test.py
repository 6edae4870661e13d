#!/usr/bin/env python3
"""The sweep's motion summary against closed forms of the geometry (issue 25).

Usage: motion_summary_test.py MECHGEN_VIEW QUICK_RETURN.so FOURBAR.so [SLIDER_CRANK.so]
(the shipped models' sweeps, `mechgen_view sweep` on their shared objects: the per-model
<model>_sweep's output, sweep_view_test.sh; at the models' default parameters, copied below).

quick_return (models/quick_return.yaml: crank r about O2 = (0, d), slotted rocker about
O4 = (0, 0), rocker L, link l, ram on y = h): the rocker's extremes are where the crank is
perpendicular to it (sin theta_crank = -r/d: 330 and 210 deg), the rocker at 90 -+ asin(r/d);
the ram's extremes at the same crank angles (B at the same height at both), so its stroke is
2 L r / d and its time ratio (pi + 2 asin(r/d)) / (pi - 2 asin(r/d)).
fourbar (a, b, c, d): the rocker's extremes where crank and coupler are collinear
(|AC| = b + a, b - a), the crank angles there from the triangle A D C, the time ratio from
them; the transmission angle cos mu = (b^2 + c^2 - a^2 - d^2 + 2 a d cos t) / (2 b c),
extreme at t = 0 and 180 deg (rows of the default sweep).
slider_crank (a, b, offset e): extremes at the dead centres, crank angles asin(e/(a+b)) and
pi + asin(e/(b-a)); stroke sqrt((a+b)^2 - e^2) - sqrt((b-a)^2 - e^2).
Every sweep is run with its rows offset from the extremes (--range over a full turn starting
at 0.37 deg, and a coarse one), so the extremes are refined between rows.
"""
import math
import re
import subprocess
import sys

failures = 0
DEG = math.pi / 180


def check(ok, what):
    global failures
    if not ok:
        failures += 1
        print("FAIL: " + what)


def close(a, b, tol, what):
    check(a is not None and abs(a - b) <= tol, "%s: %r, expected %.12g (tol %g)" % (what, a, b, tol))


def summary(tool, args):
    """tool: the sweep command, [mechgen_view, "sweep", <model>.so]."""
    p = subprocess.run(tool + ["--table", "0"] + args, stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, universal_newlines=True)
    if p.returncode != 0:
        print("FAIL: %s exit %d\n%s%s" % (" ".join(tool), p.returncode, p.stdout, p.stderr))
        sys.exit(1)
    text = p.stdout
    if "motion summary (one full turn of" not in text:
        print("FAIL: no motion summary:\n" + text)
        sys.exit(1)
    coords = {}
    name = None
    number = r"(-?[0-9.e+-]+)"
    for line in text.splitlines():
        m = re.match(r"  (\w+) \((angle|slide)\): (swing|stroke) " + number, line)
        if m:
            name = m.group(1)
            coords[name] = {"stroke": float(m.group(4))}
            continue
        m = re.match(r"    (min|max) " + number + r".* at \w+ = " + number + " deg$", line)
        if m and name:
            coords[name][m.group(1)] = float(m.group(2))
            coords[name][m.group(1) + "_at"] = float(m.group(3)) * DEG
            continue
        m = re.match(r"    rises over " + number + r" deg of \w+, falls over " + number +
                     r" deg: time ratio " + number + "$", line)
        if m and name:
            coords[name]["rising"] = float(m.group(1)) * DEG
            coords[name]["falling"] = float(m.group(2)) * DEG
            coords[name]["ratio"] = float(m.group(3))
            continue
        m = re.match(r"  transmission angle (\w+) \(sampled at the rows\): min " + number +
                     r" rad .* at \w+ = " + number + r" deg, max " + number +
                     r" rad .* at \w+ = " + number + " deg$", line)
        if m:
            coords[m.group(1)] = {"min": float(m.group(2)), "min_at": float(m.group(3)) * DEG,
                                  "max": float(m.group(4)), "max_at": float(m.group(5)) * DEG}
    return text, coords


def angle_close(a, b, tol, what):
    """a and b as angles (mod 2 pi)."""
    d = None if a is None else math.remainder(a - b, 2 * math.pi)
    close(d, 0.0, tol, what)


def quick_return(tool):
    r, d, L = 0.75, 1.5, 4.0
    beta = math.asin(r / d)
    ratio = (math.pi + 2 * beta) / (math.pi - 2 * beta)
    # Rows 1 deg apart, offset from the extremes; and rows 10 deg apart (a coarse sweep).
    for args, tol_q, tol_v in ((["--range", "theta_crank:0.37deg:360.37deg", "--steps", "360"],
                                1e-7, 1e-9),
                               (["--range", "theta_crank:0.37deg:360.37deg", "--steps", "36"],
                                1e-4, 1e-5)):
        text, c = summary(tool, args)
        rocker, ram = c.get("theta_rocker", {}), c.get("s_stroke", {})
        what = " (%s steps)" % args[-1]
        close(rocker.get("min"), math.pi / 2 - beta, tol_v, "quick_return rocker min" + what)
        close(rocker.get("max"), math.pi / 2 + beta, tol_v, "quick_return rocker max" + what)
        angle_close(rocker.get("min_at"), 2 * math.pi - beta, tol_q,
                    "quick_return crank angle at the rocker's min" + what)
        angle_close(rocker.get("max_at"), math.pi + beta, tol_q,
                    "quick_return crank angle at the rocker's max" + what)
        close(ram.get("stroke"), 2 * L * r / d, tol_v * 10, "quick_return ram stroke" + what)
        angle_close(ram.get("max_at"), 2 * math.pi - beta, tol_q, "quick_return ram max at" + what)
        angle_close(ram.get("min_at"), math.pi + beta, tol_q, "quick_return ram min at" + what)
        close(ram.get("ratio"), ratio, 10 * tol_q, "quick_return time ratio" + what)
        close(ram.get("rising"), math.pi - 2 * beta, tol_q, "quick_return ram rising interval" + what)
        close(rocker.get("ratio"), ratio, 10 * tol_q, "quick_return rocker time ratio" + what)
        # The slot's slide |O4 A| is d + r and d - r at 90 and 270 deg: ratio 1.
        slot = c.get("s_slot", {})
        close(slot.get("stroke"), 2 * r, tol_v, "quick_return slot stroke" + what)
        close(slot.get("ratio"), 1.0, 10 * tol_q, "quick_return slot time ratio" + what)


def quick_return_wrap(tool):
    """Extremes on the first and last rows of a full turn (the same configuration twice): each
    counted once, whatever the sign of K's rounding there."""
    r, d = 0.75, 1.5
    beta = math.asin(r / d)
    ratio = (math.pi + 2 * beta) / (math.pi - 2 * beta)
    text, c = summary(tool, ["--range", "theta_crank:-30deg:330deg", "--steps", "360"])
    for name in ("theta_rocker", "s_stroke"):
        close(c.get(name, {}).get("ratio"), ratio, 1e-9, name + " time ratio, extreme on the end rows")
    angle_close(c.get("theta_rocker", {}).get("min_at"), 2 * math.pi - beta, 1e-9,
                "quick_return rocker min on the end rows")


def fourbar(tool):
    a, b, c, d = 1.0, 3.5, 3.0, 4.0
    # Rocker angle (at D, from +x) and crank angle with A C of length s, C above the x axis.
    def at(s):
        theta4 = math.acos((s * s - d * d - c * c) / (2 * d * c))
        C = (d + c * math.cos(theta4), c * math.sin(theta4))
        return theta4, math.atan2(C[1], C[0])
    t4_ext, crank_ext = at(b + a)  # crank along AC
    t4_fold, crank_fold = at(b - a)
    crank_fold += math.pi  # crank opposite AC
    text, s = summary(tool, ["--range", "theta_crank:0.37deg:360.37deg", "--steps", "360"])
    rocker = s.get("theta_rocker", {})
    close(rocker.get("min"), t4_ext, 1e-9, "fourbar rocker min (extended)")
    close(rocker.get("max"), t4_fold, 1e-9, "fourbar rocker max (folded)")
    angle_close(rocker.get("min_at"), crank_ext, 1e-7, "fourbar crank angle at the rocker's min")
    angle_close(rocker.get("max_at"), crank_fold, 1e-7, "fourbar crank angle at the rocker's max")
    rise = math.fmod(crank_fold - crank_ext + 4 * math.pi, 2 * math.pi)
    close(rocker.get("rising"), rise, 1e-7, "fourbar rocker rising interval")
    close(rocker.get("ratio"), max(rise, 2 * math.pi - rise) / min(rise, 2 * math.pi - rise), 1e-7,
          "fourbar time ratio")
    # Transmission angle: the default sweep's rows include 0 and 180 deg.
    text, s = summary(tool, [])
    mu = [v for k, v in s.items() if k.startswith("mu_")]
    check(len(mu) == 1, "fourbar: one transmission angle expected:\n" + text)
    if mu:
        def mu_at(t):
            return math.acos((b * b + c * c - a * a - d * d + 2 * a * d * math.cos(t)) / (2 * b * c))
        # (12 significant digits printed)
        close(mu[0]["min"], mu_at(0), 1e-11, "fourbar mu min")
        close(mu[0]["max"], mu_at(math.pi), 1e-11, "fourbar mu max")
        angle_close(mu[0]["min_at"], 0, 1e-12, "fourbar mu min at")
        angle_close(mu[0]["max_at"], math.pi, 1e-12, "fourbar mu max at")


def slider_crank(tool):
    a, b, e = 1.0, 3.2, 0.4
    stroke = math.sqrt((a + b) ** 2 - e * e) - math.sqrt((b - a) ** 2 - e * e)
    t_max = math.asin(e / (a + b))
    t_min = math.pi + math.asin(e / (b - a))
    text, s = summary(tool, ["--range", "theta_crank:0.37deg:360.37deg", "--steps", "360"])
    slide = s.get("s_slide", {})
    close(slide.get("stroke"), stroke, 1e-9, "slider_crank stroke (offset formula)")
    close(slide.get("max"), math.sqrt((a + b) ** 2 - e * e), 1e-9, "slider_crank max")
    angle_close(slide.get("max_at"), t_max, 1e-7, "slider_crank crank angle at the far dead centre")
    angle_close(slide.get("min_at"), t_min, 1e-7, "slider_crank crank angle at the near dead centre")
    beta = t_min - t_max - math.pi
    close(slide.get("ratio"), (math.pi + beta) / (math.pi - beta), 1e-7, "slider_crank time ratio")


def main():
    sweep = lambda obj: [sys.argv[1], "sweep", obj]
    quick_return(sweep(sys.argv[2]))
    quick_return_wrap(sweep(sys.argv[2]))
    fourbar(sweep(sys.argv[3]))
    if len(sys.argv) > 4:
        slider_crank(sweep(sys.argv[4]))
    if failures:
        print("%d failure(s)" % failures)
        return 1
    print("ok: motion summaries agree with the closed forms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
