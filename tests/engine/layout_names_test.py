#!/usr/bin/env python3
"""The engine layouts have one set of names (issue 25): every preset of tools/make_engine.py is
a layout of `mechgen_balance layouts` with the same name, the same number of cylinders and,
cylinder by cylinder (the maker's numbering), the same throw and bank angles; the maker refuses
the presets' earlier names with the new one (exit 2, one line, nothing on stdout); and every
preset makes a model whose description repeats the layout's throws and banks."""
import csv
import importlib.util
import io
import os
import subprocess
import sys

root, balance = sys.argv[1], sys.argv[2]
spec = importlib.util.spec_from_file_location("make_engine", os.path.join(root, "tools", "make_engine.py"))
maker = importlib.util.module_from_spec(spec)
spec.loader.exec_module(maker)

failures = []
out = subprocess.run([balance, "layouts"], capture_output=True, text=True)
if out.returncode != 0:
    print(f"mechgen_balance layouts failed (exit {out.returncode}): {out.stderr}")
    sys.exit(1)
rows = list(csv.DictReader(line for line in io.StringIO(out.stdout) if not line.startswith("#")))
layouts = {}
for r in rows:
    layouts.setdefault(r["layout"], []).append(r)
if len(layouts) < 10:
    failures.append(f"mechgen_balance lists {len(layouts)} layouts, expected at least 10")


def same_angle(a, b):
    d = (float(a) - float(b)) % 360.0
    return min(d, 360.0 - d) < 1e-12


for name, (throws, banks, order) in sorted(maker.PRESETS.items()):
    if name not in layouts:
        failures.append(f"preset {name} of make_engine.py is not a layout of mechgen_balance")
        continue
    cylinders = layouts[name]
    if len(cylinders) != len(throws):
        failures.append(f"{name}: {len(throws)} cylinders in make_engine.py, {len(cylinders)} in mechgen_balance")
        continue
    for j, (g, b, c) in enumerate(zip(throws, banks, cylinders)):
        if int(c["cylinder"]) != j + 1 or not same_angle(g, c["throw_deg"]) or not same_angle(b, c["bank_deg"]):
            failures.append(f"{name} cylinder {j + 1}: make_engine.py throw {g} bank {b}, "
                            f"mechgen_balance cylinder {c['cylinder']} throw {c['throw_deg']} bank {c['bank_deg']}")
    if sorted(order) != list(range(1, len(throws) + 1)):
        failures.append(f"{name}: the firing order {order} is not a permutation of the cylinders")
    made = subprocess.run([sys.executable, spec.origin, "--preset", name], capture_output=True, text=True)
    if made.returncode != 0:
        failures.append(f"make_engine.py --preset {name} failed: {made.stderr.strip()}")
    elif "Throws (deg): " + ", ".join(f"{g:g}" for g in throws) not in made.stdout.replace("\n  ", " "):
        failures.append(f"make_engine.py --preset {name}: the model does not state the layout's throws")

for old, new in sorted(maker.RENAMED.items()):
    r = subprocess.run([sys.executable, spec.origin, "--preset", old], capture_output=True, text=True)
    lines = r.stderr.strip().splitlines()
    if r.returncode != 2 or r.stdout or len(lines) != 1 or f"'{new}'" not in lines[0]:
        failures.append(f"--preset {old}: expected exit 2 and one line naming '{new}', got exit "
                        f"{r.returncode}, stderr {r.stderr!r}")

for f in failures:
    print("FAIL:", f)
print(f"{len(maker.PRESETS)} presets checked against {len(layouts)} layouts, {len(failures)} failures")
sys.exit(1 if failures else 0)
