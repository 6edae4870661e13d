#!/usr/bin/env python3
"""Every CSV every tool writes states its units and signs in the file (issue 24, io/csv.h).

Runs each tool that writes a CSV (<model>_sweep, <model>_statics, <model>_simulate free and
driven, <model>_engine cycle, flywheel (three CSVs) and runup, mechgen_balance table --csv,
flywheel and wittenbauer, fourbar_balancing) and checks in every file it writes:
  * the first line is "# <tool>, model <model>: <what>" (mechgen_balance: "# mechgen_balance
    <subcommand>...: <what>"), with ". Signs: ..." where the file holds forces;
  * then one line "# name [unit]: description" per column, in the header's order, none
    missing and none extra, every unit given ("text" for a text column);
  * the header is the first line that is not a comment, and no comment line follows it;
  * every row has one cell per column, every numeric cell reads as a number, and it is the
    shortest text that reads back to that double (oracle: Python's repr, an independent
    shortest-round-trip algorithm): no digit is lost and none is printed in vain.
usage: csv_described_test.py <scratch dir> <fourbar_sweep> <slider_crank_friction_statics>
       <slider_crank_motor_simulate> <fivebar_robot_simulate> <engine_single_engine>
       <mechgen_balance> <fourbar_balancing>
"""
import math
import os
import re
import shutil
import subprocess
import sys

scratch, sweep, statics, simulate, driven, engine, balance, balancing = sys.argv[1:9]
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
failures = []


def check(ok, msg):
    if not ok:
        failures.append(msg)
        print("FAIL " + msg)


def run(args):
    p = subprocess.run(args, capture_output=True, text=True, cwd=scratch)
    check(p.returncode == 0, "%s: exit %d, stderr %s" % (" ".join(args), p.returncode, p.stderr))


def significant_digits(text):
    """The significant digits of a decimal number's text ("-1.2500e-3" -> "125")."""
    mantissa = re.split("[eE]", text.lstrip("+-"))[0].replace(".", "")
    return mantissa.lstrip("0").rstrip("0") or "0"


UNIT_LINE = re.compile(r"^# (\S+) \[([^\]]+)\](: .+)?$")


def check_csv(name, first_line, signs):
    path = os.path.join(scratch, name)
    before = len(failures)
    if not os.path.exists(path):
        check(False, "%s: not written" % name)
        return
    with open(path) as f:
        lines = f.read().splitlines()
    comments = []
    while len(comments) < len(lines) and lines[len(comments)].startswith("#"):
        comments.append(lines[len(comments)])
    check(len(comments) >= 2, "%s: %d comment lines" % (name, len(comments)))
    if len(comments) < 2 or len(lines) <= len(comments) + 1:
        check(False, "%s: no header or no rows" % name)
        return
    check(re.match(first_line, comments[0]) is not None,
          "%s: first line %r does not match %r" % (name, comments[0], first_line))
    check(("Signs: " in comments[0]) == signs, "%s: signs %s in %r" % (name, signs, comments[0]))
    header = lines[len(comments)].split(",")
    described = []
    text_columns = set()
    for line in comments[1:]:
        m = UNIT_LINE.match(line)
        check(m is not None, "%s: not a unit line: %r" % (name, line))
        if m:
            described.append(m.group(1))
            if m.group(2) == "text":
                text_columns.add(m.group(1))
    check(described == header, "%s: described columns %s, header %s" % (name, described, header))
    rows = lines[len(comments) + 1:]
    numbers = 0
    for k, row in enumerate(rows):
        check(not row.startswith("#"), "%s: a comment line after the header, row %d" % (name, k + 1))
        cells = row.split(",")
        if len(cells) != len(header):
            check(False, "%s: row %d has %d cells, header %d" % (name, k + 1, len(cells), len(header)))
            continue
        for column, cell in zip(header, cells):
            if column in text_columns or cell == "" or cell in ("nan", "inf", "-inf"):
                continue
            try:
                x = float(cell)
            except ValueError:
                check(False, "%s: row %d, %s: %r is not a number" % (name, k + 1, column, cell))
                continue
            numbers += 1
            if math.isfinite(x) and x != 0:
                shortest = significant_digits(repr(x))
                if significant_digits(cell) != shortest:
                    check(False, "%s: row %d, %s: %r, the shortest text that reads back is %r" %
                          (name, k + 1, column, cell, repr(x)))
    check(numbers > 0, "%s: no numbers" % name)
    print("%s %s: %d columns described, %d rows, %d numbers" %
          ("ok" if len(failures) == before else "FAILED", name, len(header), len(rows), numbers))


model_line = r"^# %s, model %s: "
run([sweep, "--steps", "36", "--csv", "sweep.csv", "--table", "0"])
check_csv("sweep.csv", model_line % ("fourbar_sweep", "fourbar") + "kinematic sweep", True)
run([statics, "--steps", "72", "--csv", "statics.csv", "--table", "0"])
check_csv("statics.csv",
          model_line % ("slider_crank_friction_statics", "slider_crank_friction") + "statics sweep", True)
run([simulate, "--t-end", "0.5", "--dt", "0.01", "--csv", "free.csv", "--quiet"])
check_csv("free.csv", model_line % ("slider_crank_motor_simulate", "slider_crank_motor") + "free motion",
          True)
run([driven, "--drive", "theta_prox1=move:120deg:0.1:0.6", "--drive",
     "theta_prox2=cycloidal:60deg:0:0.5", "--t-end", "0.8", "--dt", "0.02", "--csv", "driven.csv",
     "--quiet"])
check_csv("driven.csv", model_line % ("fivebar_robot_simulate", "fivebar_robot") + "driven motion", True)
engine_line = model_line % ("engine_single_engine", "engine_single")
run([engine, "cycle", "--samples", "72", "--csv", "cycle.csv"])
check_csv("cycle.csv", engine_line + "cycle", True)
run([engine, "flywheel", "--rpm", "2000", "--cs", "0.05", "--loop", "loop.csv", "--sweep", "cs.csv",
     "--wittenbauer", "witt.csv"])
check_csv("loop.csv", engine_line + "flywheel: energy loop", True)
check_csv("cs.csv", engine_line + "flywheel: C_s", True)
check_csv("witt.csv", engine_line + "flywheel: Wittenbauer", True)
run([engine, "runup", "--rpm", "2000", "--idle-rpm", "1500", "--steady-tol", "1e-4", "--dt",
     "0.0005", "--csv", "runup.csv"])
check_csv("runup.csv", engine_line + "run-up", True)

# mechgen_balance: a sampled excess torque 120 sin(theta) N m; the Wittenbauer diagram of the
# energy it writes (I = 1 + 0.1 cos theta kg m^2, T = 500 + E).
with open(os.path.join(scratch, "torque.csv"), "w") as f:
    f.write("angle_deg,T_d,T_l\n")
    for k in range(0, 360, 4):
        f.write("%d,%r,100\n" % (k, 100 + 120 * math.sin(math.radians(k))))
run([balance, "flywheel", "--torque-csv", "torque.csv", "--rpm", "600", "--cs", "0.01",
     "--energy-csv", "E.csv"])
check_csv("E.csv", r"^# mechgen_balance flywheel, from the torque table torque.csv: energy loop",
          True)
with open(os.path.join(scratch, "samples.csv"), "w") as f:
    for k in range(0, 360, 4):
        t = math.radians(k)
        f.write("%d,%r,%r\n" % (k, 1 + 0.1 * math.cos(t), 500 + 120 * (1 - math.cos(t))))
run([balance, "wittenbauer", "--csv", "samples.csv", "--diagram-csv", "D.csv"])
check_csv("D.csv", r"^# mechgen_balance wittenbauer, from the samples samples.csv: Wittenbauer",
          False)

# The balance table as CSV, on the standard output.
p = subprocess.run([balance, "table", "--csv"], capture_output=True, text=True, cwd=scratch)
check(p.returncode == 0, "mechgen_balance table --csv: exit %d" % p.returncode)
with open(os.path.join(scratch, "table.csv"), "w") as f:
    f.write(p.stdout)
check_csv("table.csv", r"^# mechgen_balance table: the balance table", True)

run([balancing, "--steps", "36", "."])
for case in ("balanced", "unbalanced"):
    check_csv("fourbar_balancing_%s.csv" % case,
              model_line % ("fourbar_balancing", "fourbar_balanced") + "%s " % case, True)

if failures:
    print("%d failure(s)" % len(failures))
    sys.exit(1)
print("PASS")
