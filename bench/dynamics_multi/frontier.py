#!/usr/bin/env python3
"""mechgen's best against Simbody's best at each accuracy, from results/simulate.csv.

For every mechgen run that is on mechgen's front (no other mechgen run is both cheaper and at
least as accurate), Simbody's CPU time at the same error (log-log interpolation of each
Simbody method's time against its error; the fastest method there) divided by mechgen's.
usage: frontier.py results/simulate.csv
"""
import csv, math, sys

runs = {}
for r in csv.DictReader(open(sys.argv[1])):
    e, t = float(r["error"]), float(r["cpu_us"])
    if e > 0 and math.isfinite(e):
        runs.setdefault(r["method"], []).append((e, t, r["tolerance"]))

def time_at(points, err):
    pts = sorted((e, t) for e, t, _ in points)
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e0 <= err <= e1:
            if e1 == e0:
                return min(t0, t1)
            a = (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0)))
    return None

ours = [(e, t, m, tol) for m, p in runs.items() if m.startswith("Mechgen") for e, t, tol in p]
front = [x for x in ours if not any(o[1] < x[1] and o[0] <= x[0] for o in ours)]
front.sort(key=lambda x: -x[0])
for ref in ("SimbodyRelease", "SimbodyDebian"):
    refs = {m: p for m, p in runs.items() if m.startswith(ref)}
    if not refs:
        continue
    print(f"  mechgen's front against {ref}'s best at equal accuracy"
          + (" (target: >= 100x)" if ref == "SimbodyRelease" else ""))
    for e, t, m, tol in front:
        best = min(((time_at(p, e), n) for n, p in refs.items() if time_at(p, e) is not None),
                   default=(None, None))
        ratio = f"{best[0] / t:6.0f}x  ({best[1][len(ref):]})" if best[0] else "  out of Simbody's range"
        print(f"    error {e:8.1e}  {m:<22} tol {tol:<6} {t:8.1f} us  {ratio}")
