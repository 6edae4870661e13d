#!/usr/bin/env python3
"""tools/make_engine.py reproduces every shipped engine model byte for byte (the command is
the model's first line), and refuses bad arguments with exit status 2 and no output."""
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
            ["--preset", "single", "--name", "bad name"], []):
    out = subprocess.run([sys.executable, maker] + bad, capture_output=True)
    if out.returncode != 2 or out.stdout or b"error" not in out.stderr:
        print(f"make_engine.py {' '.join(bad)}: expected exit 2, no output and a message; got "
              f"exit {out.returncode}, {len(out.stdout)} bytes, stderr {out.stderr!r}")
        failures += 1
print(f"{len(models)} models checked, {failures} failure(s)")
sys.exit(1 if failures else 0)
