#!/usr/bin/env python3
"""Every shipped model accepts a design section (issue 27's done-criterion; the generator
only, no compile: the derivatives of a cam, a geared, a slot and an engine model are checked
against Jets in design_derivatives_test and design_statics_test).

For each model under models/ (its own design section, or `design: {parameters: all}`
appended): `mechgen generate` succeeds, the header says kHasDesignDerivatives = true and
kDesignNames is exactly the free parameters of the YAML text (those without `derived:`) less
those written inside a cam's law (a segment's dwell/rise/return angle or lift) or a contour's
period: the oracle is the model's text read here with PyYAML, not the generator's reading.
Each parameter left out is refused when named on its own, with one error line that names the
cam, exit 1 and no files written.

Usage: every_model_design_test.py MECHGEN MODELS_DIR OUT_DIR MODEL...
"""
import os
import re
import shutil
import subprocess
import sys

import yaml

mechgen, models_dir, out_dir, names = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
os.makedirs(out_dir, exist_ok=True)
failures = []


def fail(message):
    failures.append(message)
    print("FAIL:", message)


def free_parameters(doc):
    out = []
    for name, value in (doc.get("parameters") or {}).items():
        if isinstance(value, dict) and "derived" in value:
            continue
        out.append(name)
    return out


def law_parameters(doc, params):
    """The parameters named inside a cam's law or a contour's period, by the text."""
    texts = []
    for joint in (doc.get("joints") or {}).values():
        cam = joint.get("cam") if isinstance(joint, dict) else None
        if not isinstance(cam, dict):
            continue
        for segment in cam.get("law") or []:
            for key in ("dwell", "rise", "return", "lift"):
                if key in segment:
                    texts.append(str(segment[key]))
        contour = cam.get("contour")
        if isinstance(contour, dict) and "period" in contour:
            texts.append(str(contour["period"]))
    words = set()
    for t in texts:
        words.update(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", t))
    return [p for p in params if p in words]


def generate(text, tag):
    model = os.path.join(out_dir, tag + ".yaml")
    with open(model, "w") as f:
        f.write(text)
    target = os.path.join(out_dir, tag)
    shutil.rmtree(target, ignore_errors=True)
    os.makedirs(target)
    r = subprocess.run([mechgen, "generate", model, "--name", "m", "--out-dir", target, "-q"],
                       capture_output=True, text=True)
    return r, target


if not names:
    fail("no models given")
checked = 0
for name in names:
    with open(os.path.join(models_dir, name + ".yaml")) as f:
        text = f.read()
    doc = yaml.safe_load(text)
    own = "design" in doc
    if not own:
        text += "\ndesign: {parameters: all}\n"
    r, target = generate(text, name)
    if r.returncode != 0:
        fail(f"{name}: mechgen exited {r.returncode}: {r.stderr.strip()}")
        continue
    with open(os.path.join(target, "m.h")) as f:
        header = f.read()
    if "static constexpr bool kHasDesignDerivatives = true;" not in header:
        fail(f"{name}: kHasDesignDerivatives is not true")
    m = re.search(r"kDesignNames\{ ([^}]*) \};", header)
    got = re.findall(r'"([^"]*)"', m.group(1)) if m else []
    free = free_parameters(doc)
    hidden = law_parameters(doc, free)
    if own:
        want = doc["design"] if isinstance(doc["design"], list) else doc["design"].get("parameters")
        want = [p for p in free if p not in hidden] if want == "all" else want
    else:
        want = [p for p in free if p not in hidden]
    if got != want:
        fail(f"{name}: kDesignNames {got}, the text's free parameters less the cams' laws' {want}")
    for p in hidden:
        r, target = generate(text.replace("design: {parameters: all}", f"design: [{p}]"), name + "_" + p)
        lines = r.stderr.strip().splitlines()
        if r.returncode != 1 or len(lines) != 1 or f"design parameter '{p}' is inside the law of cam" not in r.stderr:
            fail(f"{name}: naming '{p}' gave exit {r.returncode} and {r.stderr.strip()!r}")
        if os.listdir(target):
            fail(f"{name}: naming '{p}' left files {os.listdir(target)}")
        checked += 1
    checked += 1
    print(f"{name}: {len(got)} design parameters" + (f", left out (in a cam's law): {hidden}" if hidden else ""))

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print(f"ok: {len(names)} models, {checked} generations")
