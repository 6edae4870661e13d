#!/usr/bin/env python3
"""Writes a cascade of N four-bar loops (2N + 2 links, N loops, mobility 1) to stdout.

Stage 1 is the four-bar of models/fourbar.yaml; stage k > 1 drives a new coupler/rocker
pair from the previous rocker's tip, the new rocker pivoting on ground at (k d, 0).
Used by the degenerate_models ctest (N = 100: 202 links) to check that mechgen answers
within bounded time and memory, with a result or a clear message.

  python3 fuzz/degenerate/make_huge.py 100 > huge_cascade.yaml
"""
import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 100
out = []
w = out.append
w(f"name: huge_cascade_{n}")
w(f"title: Cascade of {n} four-bar loops ({2 * n + 2} links)")
w("parameters:")
w("  a: {value: 1.0}")
w("  b: {value: 3.5}")
w("  c: {value: 3.0}")
w("  d: {value: 4.0}")
ground = ", ".join(f"D{k}: [{k}*d, 0]" for k in range(1, n + 1))
w("links:")
w(f"  ground: {{ground: true, points: {{A: [0, 0], {ground}}}}}")
w("  crank: {points: {A: [0, 0], B: [a, 0]}}")
for k in range(1, n + 1):
    w(f"  coupler{k}: {{points: {{B: [0, 0], C: [b, 0]}}}}")
    w(f"  rocker{k}: {{points: {{D: [0, 0], C: [c, 0], E: [0, c/3]}}}}")
w("joints:")
w("  A: {revolute: [ground.A, crank.A]}")
for k in range(1, n + 1):
    driver = "crank.B" if k == 1 else f"rocker{k - 1}.E"
    w(f"  B{k}: {{revolute: [{driver}, coupler{k}.B]}}")
    w(f"  C{k}: {{revolute: [coupler{k}.C, rocker{k}.C]}}")
    w(f"  D{k}: {{revolute: [rocker{k}.D, ground.D{k}]}}")
w("inputs:")
w("  - {joint: A, range: [0, 360*deg]}")
w("outputs:")
w("  order: 2")
print("\n".join(out))
