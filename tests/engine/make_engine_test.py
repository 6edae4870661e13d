#!/usr/bin/env python3
"""tools/make_engine.py reproduces every shipped engine model byte for byte (the command is
the model's first line), and refuses bad arguments (among them every non-finite or
out-of-range number) with exit status 2, one line on stderr and no output; a model made with
in-range extremes holds no inf or nan."""
import glob
import os
import shlex
import subprocess
import sys

root = sys.argv[1]
maker = os.path.join(root, "tools", "make_engine.py")
failures = 0
models = sorted(glob.glob(os.path.join(root, "models", "engine_*.yaml")))
if len(models) < 3:
    print(f"expected at least 3 engine models in models/, found {len(models)}")
    sys.exit(1)
for path in models:
    with open(path, "rb") as f:
        text = f.read()
    first = text.split(b"\n", 1)[0].decode()
    prefix = "# Made by: tools/make_engine.py "
    if not first.startswith(prefix):
        print(f"{path}: the first line does not name the maker's command")
        failures += 1
        continue
    out = subprocess.run([sys.executable, maker] + shlex.split(first[len(prefix):]),
                         capture_output=True)
    if out.returncode != 0 or out.stdout != text:
        print(f"{path}: the maker's output differs (exit {out.returncode}): run {first[2:]}")
        failures += 1
for bad in (["--preset", "nosuch"], ["--preset", "single", "--bore", "-1"],
            ["--preset", "inline4", "--order", "1-2-2-3"], ["--preset", "single", "--strokes", "3"],
            ["--preset", "single", "--rod-length", "0.04"], ["--preset", "inline4", "--banks", "0,0"],
            ["--preset", "single", "--name", "bad name"], [],
            # Issue 24: non-finite or out-of-range numbers (inf once wrote nan into a model).
            ["--preset", "inline4", "--pitch", "inf"], ["--preset", "inline4", "--pitch=-inf"],
            ["--preset", "inline4", "--pitch", "nan"], ["--preset", "inline4", "--pitch", "1e999"],
            ["--preset", "inline4", "--pitch", "1e300"], ["--preset", "single", "--bore", "inf"],
            ["--preset", "single", "--bore", "nan"], ["--preset", "single", "--stroke", "1e200"],
            ["--preset", "single", "--rod-length", "inf"], ["--preset", "single", "--offset", "nan"],
            ["--preset", "single", "--offset", "-1e300"], ["--preset", "single", "--m-rod", "inf"],
            ["--preset", "single", "--l-G", "nan"], ["--preset", "single", "--J-rod", "1e308"],
            ["--preset", "single", "--m-pis", "-inf"], ["--preset", "single", "--m-crank", "nan"],
            ["--preset", "single", "--J-fly", "inf"], ["--preset", "single", "--T-load", "inf"],
            ["--preset", "single", "--T-load", "-1"], ["--preset", "single", "--c-load", "nan"],
            ["--preset", "v8_crossplane", "--v-angle", "nan"], ["--preset", "v8_crossplane", "--v-angle", "inf"],
            ["--preset", "inline2_180", "--throws", "0,inf"], ["--preset", "inline2_180", "--throws", "0,1e300"],
            ["--preset", "inline2_180", "--banks", "nan,0"], ["--preset", "inline2_180", "--z", "0,inf"],
            ["--preset", "inline2_180", "--z", "nan,0"], ["--preset", "inline2_180", "--z", "0,1e300"],
            ["--preset", "inline4", "--order", "1-3-4-1e999"], ["--preset", "single", "--strokes", "inf"]):
    out = subprocess.run([sys.executable, maker] + bad, capture_output=True)
    if (out.returncode != 2 or out.stdout or b"error" not in out.stderr
            or out.stderr.count(b"\n") != 1):
        print(f"make_engine.py {' '.join(bad)}: expected exit 2, no output and a one-line message; got "
              f"exit {out.returncode}, {len(out.stdout)} bytes, stderr {out.stderr!r}")
        failures += 1
# In-range extremes: a model, all of whose numbers are finite.
for good in (["--preset", "inline4", "--pitch", "-1000", "--bore", "1000", "--stroke", "2",
              "--rod-length", "1000", "--J-fly", "1e6", "--T-load", "1e7"],
             ["--preset", "inline2_180", "--throws=-720,720", "--z=1e3,-1e3"]):
    out = subprocess.run([sys.executable, maker] + good, capture_output=True)
    low = out.stdout.lower()
    if out.returncode != 0 or not out.stdout or b"nan" in low or b"inf" in low.replace(b"inline", b""):
        print(f"make_engine.py {' '.join(good)}: expected a finite model; got exit {out.returncode}, "
              f"stderr {out.stderr!r}")
        failures += 1
print(f"{len(models)} models checked, {failures} failure(s)")
sys.exit(1 if failures else 0)
