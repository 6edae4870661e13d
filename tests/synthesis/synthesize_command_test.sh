#!/usr/bin/env bash
# `mechgen synthesize MODEL --task TASK.yaml` (runtime/tools/synthesize_main.cc), end to end,
# in a temporary directory with a private cache (one compile of the tool, for fourbar):
#   - a task file with an error: exit 1, FILE:LINE:COLUMN: error: on stderr, nothing written;
#     a directory as the task: exit 1, FILE: error: ...;
#   - a bad option (--threads 0, --seed -1): exit 2, one line, nothing written;
#   - a task nothing satisfies (links longer than the variables' bounds allow): exit 3,
#     nothing written;
#   - the shipped four-bar's own coupler points (tasks/fourbar_refind.yaml): exit 0; the model
#     file, path.svg and report.txt written; the model file is the input with only the
#     parameter values and the assembly's values (the first target's configuration) changed,
#     `mechgen generate` accepts it, and its coupler curve, computed here by hand formulas
#     (circle-circle intersection, Python) from the values read back from the file, passes
#     through every target to 1e-9;
#   - the same seed with --threads 1 and --threads 2: the model files and the reports' error
#     lines byte-identical;
#   - function generation as `mechgen synthesize TASK` (the task names its model): three pairs
#     computed here by hand formulas, the model file's values meet them to 1e-12; the command
#     form's errors (no `model:` in the task: exit 1; `--task` as well: exit 2);
#   - a function over a range (log10 on [1, 2], five Chebyshev points, free start angles):
#     the report's structural error over the range against the hand formula, the same model
#     file with 1 and 2 threads, its range narrowed (a triple rocker) and `mechgen generate`
#     accepting it; a bad expression: exit 1 with FILE:LINE:COLUMN;
#   - four poses of the shipped four-bar's coupler (hand formulas): curves.csv and curves.svg;
#   - exact synthesis (kind: exact): below;
#   - the model view (issue 43) against the per-model program: at the end.
# usage: synthesize_command_test.sh <mechgen> <source dir> <python3>
set -uo pipefail
mechgen=$(realpath "$1") source_dir=$(realpath "$2") python=$3
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
cd "$root" || exit 1
export MECHGEN_CACHE_DIR=$root/cache
cp "$source_dir/models/fourbar.yaml" fourbar.yaml
task=$source_dir/tests/synthesis/tasks/fourbar_refind.yaml
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { echo "ok $*"; }

# A bad task file: where and what, nothing written (the tool compiles here, once).
printf 'synthesis: path\npoint: coupler.P\ntargets: [[0, 0], [1, 1]]\nvariables: {a: [2, 1]}\n' > bad.yaml
"$mechgen" synthesize fourbar.yaml --task bad.yaml --out out_bad > bad.out 2> bad.err
status=$?
[ "$status" = 1 ] || fail "bad task: exit $status, expected 1"
grep -q '^bad.yaml:4:16: error: variable a: min must be below max$' bad.err || fail "bad task: $(tail -1 bad.err)"
[ ! -e out_bad ] || fail "bad task: out_bad written"
ok "bad task file"

# A directory as the task (once an uncaught std::ios_base::failure): one located line, exit 1.
mkdir -p taskdir
"$mechgen" synthesize fourbar.yaml --task taskdir --out out_dir > dir.out 2> dir.err
status=$?
[ "$status" = 1 ] || fail "directory as task: exit $status, expected 1"
[ "$(cat dir.err)" = "taskdir: error: the path is a directory, not a task file; give the path of a .yaml file" ] ||
  fail "directory as task: $(cat dir.err)"
[ ! -e out_dir ] || fail "directory as task: out_dir written"
ok "directory as task"

"$mechgen" synthesize fourbar.yaml --task "$task" --threads 0 --out out_opt > opt.out 2> opt.err
status=$?
[ "$status" = 2 ] || fail "bad option: exit $status, expected 2"
[ "$(wc -l < opt.err)" = 1 ] || fail "bad option: $(cat opt.err)"
[ ! -e out_opt ] || fail "bad option: out_opt written"
ok "bad option"
# A negative seed is not a seed (it once wrapped round to 2^64 - 1 and ran).
"$mechgen" synthesize fourbar.yaml --task "$task" --seed -1 --out out_seed > seed.out 2> seed.err
status=$?
[ "$status" = 2 ] || fail "--seed -1: exit $status, expected 2"
[ "$(wc -l < seed.err)" = 1 ] || fail "--seed -1: $(cat seed.err)"
[ ! -e out_seed ] || fail "--seed -1: out_seed written"
ok "negative seed"

# Nothing feasible: every link at least 10, the variables at most 6.
sed 's/^  transmission_angle: .*/  link_lengths: [10, 20]/; s/evaluations: 20000/evaluations: 400/' "$task" > none.yaml
"$mechgen" synthesize fourbar.yaml --task none.yaml --out out_none > none.out 2> none.err
status=$?
[ "$status" = 3 ] || fail "infeasible task: exit $status, expected 3"
grep -q 'no mechanism satisfies' none.err || fail "infeasible task: $(tail -1 none.err)"
[ ! -e out_none ] || fail "infeasible task: out_none written"
ok "infeasible task"

# The four-bar's own coupler points.
"$mechgen" synthesize fourbar.yaml --task "$task" --seed 5 --threads 1 --out out1 > run1.out 2> run1.err
status=$?
[ "$status" = 0 ] || { fail "refind: exit $status"; cat run1.err; }
for f in fourbar.yaml path.svg report.txt; do [ -s "out1/$f" ] || fail "refind: out1/$f missing"; done
"$mechgen" generate out1/fourbar.yaml -o "$root" > gen.out 2>&1 || fail "mechgen generate refuses the synthesized model: $(cat gen.out)"
# Only parameter values and the assembly's values (the configuration at the first target)
# differ from the input model.
diff fourbar.yaml out1/fourbar.yaml | grep '^[<>]' | grep -v -e '{value: ' -e '^[<>]   theta_\(crank\|coupler\|rocker\): ' &&
  fail "lines other than parameter and assembly values changed"
grep -q '^  theta_crank: 90\*deg$' out1/fourbar.yaml && fail "the assembly's input not written"
grep -q '^  assembly: theta_crank = ' out1/report.txt || fail "the report does not say what the model file's assembly is"
"$python" - "$task" out1/fourbar.yaml <<'PY' || fail "the synthesized coupler curve misses a target"
import math, re, sys
task, model = sys.argv[1], sys.argv[2]
values = dict(re.findall(r'^  (\w+):\s*\{value: ([^,]+),', open(model).read(), re.M))
a, b, c, d, xi, eta = (float(values[k]) for k in ('a', 'b', 'c', 'd', 'xi', 'eta'))
targets = [tuple(map(float, m)) for m in re.findall(r'^  - \[([^,]+), ([^\]]+)\]', open(task).read(), re.M)]
def P(t):  # the open assembly: C to the left of B -> D
    Bx, By = a * math.cos(t), a * math.sin(t)
    ex, ey = d - Bx, -By
    L = math.hypot(ex, ey)
    s = (b * b - c * c + L * L) / (2 * L)
    h = math.sqrt(max(b * b - s * s, 0.0))
    Cx, Cy = Bx + s * ex / L - h * ey / L, By + s * ey / L + h * ex / L
    ux, uy = (Cx - Bx) / b, (Cy - By) / b
    return Bx + xi * ux - eta * uy, By + xi * uy + eta * ux
worst = 0.0
for tx, ty in targets:
    dist = lambda t: math.hypot(P(t)[0] - tx, P(t)[1] - ty)
    t = min((2 * math.pi * k / 3600 for k in range(3600)), key=dist)
    lo, hi = t - 2 * math.pi / 3600, t + 2 * math.pi / 3600
    for _ in range(200):  # golden section on the distance
        m1, m2 = lo + 0.382 * (hi - lo), hi - 0.382 * (hi - lo)
        lo, hi = (lo, m2) if dist(m1) < dist(m2) else (m1, hi)
    worst = max(worst, dist(0.5 * (lo + hi)))
print("largest distance to a target: %.3g" % worst)
sys.exit(0 if worst < 1e-9 else 1)
PY
ok "refind: model file, generate, the curve through the targets"

# The same seed, two threads: the same bytes.
"$mechgen" synthesize fourbar.yaml --task "$task" --seed 5 --threads 2 --out out2 > run2.out 2> run2.err || fail "refind, 2 threads"
cmp -s out1/fourbar.yaml out2/fourbar.yaml || fail "the model files differ between 1 and 2 threads"
cmp -s <(grep -v -e '^search:' -e '^evaluations:' out1/report.txt) <(grep -v -e '^search:' -e '^evaluations:' out2/report.txt) ||
  fail "the reports differ between 1 and 2 threads"
ok "same bytes with 1 and 2 threads"

# Function generation in the command form `mechgen synthesize TASK` (the task names its model,
# relative to the task file): three pairs of the four-bar computed here by hand (circle
# intersection), Freudenstein's exact answer; the model file's a, b, c read back put the rocker
# at the pairs' angles (hand formula again) to 1e-12.
"$python" - > function.yaml <<'PY'
import math
a, b, c, d = 1.0, 3.5, 3.0, 4.0
def t4(t2):
    bx, by = a * math.cos(t2) - d, a * math.sin(t2)
    e2 = bx * bx + by * by
    return math.atan2(by, bx) - math.acos((c * c + e2 - b * b) / (2 * c * math.sqrt(e2)))
print("synthesis: function\nmodel: fourbar.yaml\noutput: theta_rocker\npairs:")
for deg in (35, 80, 125):
    t = math.radians(deg)
    print("  - [%.17g, %.17g]" % (t, t4(t)))
print("freudenstein: {crank: a, coupler: b, rocker: c, ground: d}")
print("variables: {a: [0.5, 6], b: [0.5, 6], c: [0.5, 6]}\nsearch: {restarts: 2}")
PY
"$mechgen" synthesize function.yaml --out out_fn > fn.out 2> fn.err
status=$?
[ "$status" = 0 ] || { fail "function task: exit $status"; cat fn.err; }
for f in fourbar.yaml function.svg report.txt; do [ -s "out_fn/$f" ] || fail "function task: out_fn/$f missing"; done
"$python" - function.yaml out_fn/fourbar.yaml <<'PY' || fail "the synthesized rocker misses a pair"
import math, re, sys
task, model = sys.argv[1], sys.argv[2]
values = dict(re.findall(r'^  (\w+):\s*\{value: ([^,]+),', open(model).read(), re.M))
a, b, c, d = (float(values[k]) for k in ('a', 'b', 'c', 'd'))
worst = 0.0
for t2, psi in re.findall(r'^  - \[([^,]+), ([^\]]+)\]', open(task).read(), re.M):
    t2, psi = float(t2), float(psi)
    bx, by = a * math.cos(t2) - d, a * math.sin(t2)
    e2 = bx * bx + by * by
    t4 = math.atan2(by, bx) - math.acos((c * c + e2 - b * b) / (2 * c * math.sqrt(e2)))
    worst = max(worst, abs(t4 - psi))
print("largest rocker angle error: %.3g rad" % worst)
sys.exit(0 if worst < 1e-12 else 1)
PY
ok "function task (mechgen synthesize TASK): exact three pairs, the model file meets them"

# The command form's errors: a task naming no model (exit 1), a task with --task as well (exit 2).
grep -v '^model:' function.yaml > nomodel.yaml
"$mechgen" synthesize nomodel.yaml --out out_nm > nm.out 2> nm.err
status=$?
[ "$status" = 1 ] || fail "task without model: exit $status, expected 1"
grep -Eq "^nomodel.yaml:[0-9]+:1: error: a task run as .mechgen synthesize nomodel.yaml. names its model" nm.err ||
  fail "task without model: $(cat nm.err)"
[ "$(wc -l < nm.err)" = 1 ] || fail "task without model: $(cat nm.err)"
"$mechgen" synthesize function.yaml --task function.yaml --out out_tt > tt.out 2> tt.err
status=$?
[ "$status" = 2 ] || fail "task with --task: exit $status, expected 2"
[ "$(wc -l < tt.err)" = 1 ] || fail "task with --task: $(cat tt.err)"
[ ! -e out_nm ] && [ ! -e out_tt ] || fail "an error wrote output"
ok "the command form's errors"

# A function over a range (`function:`, Chebyshev points) with free start angles, as `mechgen
# synthesize TASK`: the structural error the report gives over the range against the hand
# formula (the rocker by circle intersection) for the lengths read back from the model file
# and the start angles from the report; the same model file with 1 and 2 threads.
cat > log10.yaml <<'YAML'
synthesis: function
model: fourbar.yaml
output: theta_rocker
function: {expression: "log10(x)", x: [1, 2], input: [90deg, 150deg], output: [20deg, 80deg], points: 5}
free_start: {input: [30deg, 150deg], output: [-60deg, 60deg]}
freudenstein: {crank: a, coupler: b, rocker: c, ground: d}
variables: {a: [0.5, 20], b: [0.5, 20], c: [0.5, 20]}
search: {restarts: 2, evaluations: 4000}
YAML
"$mechgen" synthesize log10.yaml --seed 3 --threads 1 --out out_log1 > log1.out 2> log1.err
status=$?
[ "$status" = 0 ] || { fail "log10 task: exit $status"; cat log1.err; }
"$mechgen" synthesize log10.yaml --seed 3 --threads 2 --out out_log2 > log2.out 2> log2.err || fail "log10 task, 2 threads"
cmp -s out_log1/fourbar.yaml out_log2/fourbar.yaml || fail "log10 task: the model files differ between 1 and 2 threads"
grep -q 'stroke-dasharray' out_log1/function.svg || fail "log10 task: function.svg has no function curve"
# Its four-bar is a non-Grashof triple rocker: the model file's range is narrowed to the motion
# through the pairs (the generator refused the model's [0, 360 deg] before), and the generator
# accepts the file.
grep -q '^  - {joint: A, range: \[0, 360\*deg\]}$' out_log1/fourbar.yaml && fail "log10 task: the range not narrowed"
"$mechgen" generate out_log1/fourbar.yaml -o "$root" > gen_log.out 2>&1 ||
  fail "mechgen generate refuses the function task's model file: $(cat gen_log.out)"
"$python" - out_log1/fourbar.yaml out_log1/report.txt <<'PY' || fail "log10 task: the structural error does not match the hand formula"
import math, re, sys
model, report = open(sys.argv[1]).read(), open(sys.argv[2]).read()
values = dict(re.findall(r'^  (\w+):\s*\{value: ([^,]+),', model, re.M))
a, b, c, d = (float(values[k]) for k in ('a', 'b', 'c', 'd'))
in0, out0 = (math.radians(float(v)) for v in re.search(r'^start angles: input (\S+) deg, output (\S+) deg', report, re.M).groups())
largest = float(re.search(r'^structural error over the range \(201 samples\): largest (\S+) in y', report, re.M).group(1))
span = math.radians(60)
worst = 0.0
for k in range(201):
    x = 1 + k / 200.0
    t2 = in0 + span * (x - 1)
    bx, by = a * math.cos(t2) - d, a * math.sin(t2)
    e2 = bx * bx + by * by
    t4 = math.atan2(by, bx) - math.acos((c * c + e2 - b * b) / (2 * c * math.sqrt(e2)))
    worst = max(worst, abs(math.log10(2) * (t4 - out0) / span - math.log10(x)))
print("structural error: report %.6g, hand %.6g" % (largest, worst))
sys.exit(0 if abs(largest - worst) <= 1e-5 * worst else 1)
PY
ok "function over a range with free start angles: structural error by hand, same bytes with 1 and 2 threads"

# A bad expression: where and what, exit 1, nothing written.
sed 's/"log10(x)"/"log10(x) +* 2"/' log10.yaml > badexpr.yaml
"$mechgen" synthesize badexpr.yaml --out out_be > be.out 2> be.err
status=$?
[ "$status" = 1 ] || fail "bad expression: exit $status, expected 1"
grep -q "^badexpr.yaml:4:35: error: function.expression: unexpected '\*'$" be.err || fail "bad expression: $(cat be.err)"
[ ! -e out_be ] || fail "bad expression: out_be written"
ok "bad expression"

# Four poses of the shipped four-bar's coupler (hand formulas): curves.csv and curves.svg.
"$python" - > poses4.yaml <<'PY'
import math
a, b, c, d, xi, eta = 1.0, 3.5, 3.0, 4.0, 1.5, 1.0
print("synthesis: motion\nmodel: fourbar.yaml\npoint: coupler.P\ncoupler_angle: theta_coupler\nsearch: {curve_rays: 720}\nposes:")
for deg in (20, 60, 110, 170):
    t = math.radians(deg)
    Bx, By = a * math.cos(t), a * math.sin(t)
    ex, ey = d - Bx, -By
    L = math.hypot(ex, ey)
    s = (b * b - c * c + L * L) / (2 * L)
    h = math.sqrt(b * b - s * s)
    Cx, Cy = Bx + s * ex / L - h * ey / L, By + s * ey / L + h * ex / L
    ux, uy = (Cx - Bx) / b, (Cy - By) / b
    print("  - [%.17g, %.17g, %.17g]" % (Bx + xi * ux - eta * uy, By + xi * uy + eta * ux, math.atan2(uy, ux)))
PY
"$mechgen" synthesize poses4.yaml --out out_m4 > m4.out 2> m4.err
status=$?
[ "$status" = 0 ] || { fail "four poses: exit $status"; cat m4.err; }
for f in curves.csv curves.svg report.txt; do [ -s "out_m4/$f" ] || fail "four poses: out_m4/$f missing"; done
[ "$(grep -c 'fill="#1f5fa8"' out_m4/curves.svg)" -gt 100 ] || fail "four poses: curves.svg has few circle points"
[ "$(grep -c 'fill="#c0392b"' out_m4/curves.svg)" -gt 100 ] || fail "four poses: curves.svg has few centre points"
[ "$(grep -c '<line' out_m4/curves.svg)" = 4 ] || fail "four poses: curves.svg does not draw the four poses"
ok "four poses: curves.csv and curves.svg"

# Exact synthesis (`kind: exact`) in the command form, on the shipped four-bar (its frame fixed:
# A = (0, 0), D = (d, 0), so the task names no x0, y0, theta0):
#   - Morgan and Wampler's Problem 7 (the shipped task file with this model): exit 0,
#     solutions.csv says complete, 33 isolated solutions, 15 real, one model file per real
#     one, each accepted by `mechgen generate`, each with the coupler point at point 1 by hand
#     formulas (circle intersection on the side of BD the CSV gives) from the values read back;
#   - a crank-rocker's own coupler points on the side of BD opposite to the model's assembly
#     (hand formulas): the four-bar found again defect-free, its model file written on the
#     mirror mode, and `mechgen sweep` of that file puts the coupler point on each of the five
#     points at the CSV's crank angles (1e-8);
#   - five targets that are four: exit 1, FILE:LINE:COLUMN: error:, nothing written.
sed -e 's|^model: .*|model: fourbar.yaml|' \
    -e 's|^parameters: .*|parameters: {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta}|' \
    "$source_dir/tests/synthesis/benchmarks/problem7_exact.yaml" > problem7.yaml
"$mechgen" synthesize problem7.yaml --out out_p7 > p7.out 2> p7.err
status=$?
[ "$status" = 0 ] || { fail "problem 7: exit $status"; cat p7.err; }
grep -q '^# status: complete; paths 256, nonsingular solutions 33 (real 15, complex 18)' out_p7/solutions.csv ||
  fail "problem 7: $(grep '^# status' out_p7/solutions.csv)"
[ "$(ls out_p7/fourbar_exact_*.yaml | wc -l)" = 15 ] || fail "problem 7: $(ls out_p7 | tr '\n' ' ')"
for m in out_p7/fourbar_exact_*.yaml; do
  "$mechgen" generate "$m" -o "$root" -q > gen_p7.out 2>&1 || fail "mechgen generate refuses $m: $(cat gen_p7.out)"
done
"$python" - out_p7 <<'PY' || fail "problem 7: a written model misses point 1"
import csv, glob, math, re, sys
out = sys.argv[1]
rows = list(csv.DictReader(l for l in open(out + "/solutions.csv") if not l.startswith("#")))
P1 = (0.50, 1.06)
worst, n = 0.0, 0
for r in rows:
    if r["status"] != "real":
        continue
    text = open(out + "/" + r["model_file"]).read()
    v = {k: float(x) for k, x in re.findall(r'^  (\w+):\s*\{value: ([^,]+),', text, re.M)}
    a, b, c, d, xi, eta = (v[k] for k in ("a", "b", "c", "d", "xi", "eta"))
    q, side = float(r["crank_1"]), int(r["branch_1"])
    Bx, By = a * math.cos(q), a * math.sin(q)
    ex, ey = d - Bx, -By
    L = math.hypot(ex, ey)
    s = (b * b - c * c + L * L) / (2 * L)
    h = side * math.sqrt(b * b - s * s)
    Cx, Cy = Bx + (s * ex - h * ey) / L, By + (s * ey + h * ex) / L
    ux, uy = (Cx - Bx) / b, (Cy - By) / b
    worst = max(worst, math.hypot(Bx + xi * ux - eta * uy - P1[0], By + xi * uy + eta * ux - P1[1]))
    n += 1
print("%d real solutions, largest distance from point 1: %.3g" % (n, worst))
sys.exit(0 if n == 15 and worst < 1e-8 else 1)
PY
ok "exact synthesis: Problem 7, 33 solutions, 15 model files, generate accepts them, point 1 by hand"

"$python" - > own.yaml <<'PY'
import math
a, b, c, d, xi, eta = 1.0, 3.5, 3.0, 4.0, 1.5, 1.0
print("synthesis: path\nkind: exact\nmodel: fourbar.yaml\npoint: coupler.P\npivots: {crank: [0, 0], rocker: [4, 0]}\ntargets:")
for q in (0.3, 1.2, 2.0, 3.1, 4.4):  # C on the right of B -> D: the mirror of the model's open assembly
    Bx, By = a * math.cos(q), a * math.sin(q)
    ex, ey = d - Bx, -By
    L = math.hypot(ex, ey)
    s = (b * b - c * c + L * L) / (2 * L)
    h = -math.sqrt(b * b - s * s)
    Cx, Cy = Bx + (s * ex - h * ey) / L, By + (s * ey + h * ex) / L
    ux, uy = (Cx - Bx) / b, (Cy - By) / b
    print("  - [%.17g, %.17g]" % (Bx + xi * ux - eta * uy, By + xi * uy + eta * ux))
print("parameters: {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta}")
PY
"$mechgen" synthesize own.yaml --out out_own > own.out 2> own.err
status=$?
[ "$status" = 0 ] || { fail "own points: exit $status"; cat own.err; }
# The row of the original four-bar: defect-free, on the mirror mode (-1 against the model's +1).
line=$(grep -v '^#' out_own/solutions.csv | "$python" -c '
import csv, sys
for r in csv.DictReader(sys.stdin):
    if r["status"] == "real" and abs(float(r["a"]) - 1) + abs(float(r["b"]) - 3.5) + abs(float(r["c"]) - 3) < 1e-8:
        print(r["model_file"], r["defect"] or "none", r["mode"], *(r["crank_%d" % j] for j in range(1, 6)))')
set -- $line
[ "$#" = 8 ] && [ "$2" = none ] || fail "own points: the original four-bar not found defect-free: $line"
model_file=$1 mode=$3
shift 3
j=0
for q in "$@"; do
  j=$((j + 1))
  hi=$("$python" -c "print(repr($q + 0.01))")
  "$mechgen" sweep "out_own/$model_file" --range "theta_crank:$q:$hi" --steps 1 --csv "sweep_own_$j.csv" > sweep_own.out 2>&1 ||
    { fail "mechgen sweep of $model_file at point $j: $(tail -2 sweep_own.out)"; continue; }
  "$python" - "sweep_own_$j.csv" own.yaml "$j" <<'PY' || fail "mechgen sweep of $model_file misses point $j"
import csv, re, sys
rows = list(csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith("#")))
targets = re.findall(r'^  - \[([^,]+), ([^\]]+)\]', open(sys.argv[2]).read(), re.M)
tx, ty = (float(v) for v in targets[int(sys.argv[3]) - 1])
d = ((float(rows[0]["coupler.P.x"]) - tx) ** 2 + (float(rows[0]["coupler.P.y"]) - ty) ** 2) ** 0.5
print("point %s: %.3g" % (sys.argv[3], d))
sys.exit(0 if d < 1e-8 else 1)
PY
done
[ "$mode" = -1 ] || fail "own points: written on mode $mode, expected the mirror -1"
ok "exact synthesis: a crank-rocker's own points on the mirror mode, mechgen sweep of the written model through them"

sed 's|^targets: .*|targets: [[0.50, 1.06], [-0.83, -0.27], [-0.34, 0.22], [-0.13, 0.43]]|' problem7.yaml > four.yaml
"$mechgen" synthesize four.yaml --out out_four > four.out 2> four.err
status=$?
[ "$status" = 1 ] || fail "four targets: exit $status, expected 1"
grep -Eq '^four.yaml:[0-9]+:10: error: targets: kind: exact takes exactly five precision points' four.err || fail "four targets: $(cat four.err)"
[ ! -e out_four ] || fail "four targets: out_four written"
ok "exact synthesis: four targets refused"

# The model view (issue 43): `mechgen synthesize` runs path generation, motion generation,
# exact synthesis and function generation through the runtime compiled once (mechgen_view
# synthesize on the model's shared object) and builds no per-model program for them (a cache of
# its own: only view/ in it; the sections above neither); the per-model program (MECHGEN_VIEW=0)
# gives the same output files, standard output and standard error (mechgen's own compile lines
# apart, and the time and thread id of Ceres' log lines) byte for byte, the reports' times apart
# (the wall and CPU seconds):
#   - the four-bar's own coupler points (path generation, seed 5, 1 thread): model file,
#     path.svg, report.txt;
#   - four poses (above): curves.csv, curves.svg, report.txt;
#   - Problem 7 and the crank-rocker's own points (kind: exact, above): every model file,
#     solutions.csv, report.txt;
#   - the function tasks above (three pairs, Freudenstein's exact start; log10 over a range with
#     free start angles, 2 threads): model file, function.svg, report.txt.
# (Five and six poses with the model file written: synthesis_test's ViewSynthesis.*, in one
# process, on synth_fourbar, whose nine parameters a motion task needs; so are a path and an
# exact task.)
[ -d cache/view ] && [ ! -d cache/synthesize ] ||
  fail "the sections above: not through the model view alone ($(ls cache | tr '\n' ' '))"
cp "$task" refind.yaml
for way in view fixed; do
  mkdir -p "$way"
  cp fourbar.yaml refind.yaml poses4.yaml problem7.yaml own.yaml function.yaml log10.yaml "$way/"
  for t in refind poses4 problem7 own function log10; do
    options=()
    [ "$t" = refind ] && options=(--seed 5 --threads 1 --task refind.yaml)
    [ "$t" = log10 ] && options=(--seed 3 --threads 2)
    [ "$t" = refind ] && model=fourbar.yaml || model=$t.yaml
    if [ "$way" = view ]; then
      (cd view && MECHGEN_CACHE_DIR=$root/cache_view "$mechgen" synthesize "$model" "${options[@]}" --out "out_$t" > "$t.out" 2> "$t.err")
    else
      (cd fixed && MECHGEN_VIEW=0 "$mechgen" synthesize "$model" "${options[@]}" --out "out_$t" > "$t.out" 2> "$t.err")
    fi
    status=$?
    [ "$status" = 0 ] || { fail "$t through the $way: exit $status"; cat "$way/$t.err"; }
    # (glog's lines from Ceres, e.g. an LM run refused its next evaluation by the budget, with
    # their time and thread id dropped)
    grep -v '^mechgen: ' "$way/$t.err" | sed -E 's/^([EWIF])[0-9]{8} [0-9:.]+ +[0-9]+ /\1 /' > "$way/$t.err.tool"
    [ -f "$way/out_$t/report.txt" ] &&
      sed -i -e '/^time: .* s (the continuation)$/d' -e 's/, wall [^ ]* s, cpu [^ ]* s$//' "$way/out_$t/report.txt" "$way/$t.out"
  done
done
[ "$(ls cache_view)" = view ] || fail "mechgen synthesize through the view built more than the model's object: $(ls cache_view | tr '\n' ' ')"
[ -s view/out_refind/fourbar.yaml ] && [ -s view/out_poses4/curves.csv ] && [ "$(ls view/out_problem7/*_exact_*.yaml | wc -l)" = 15 ] &&
  [ -s view/out_function/fourbar.yaml ] && [ -s view/out_log10/function.svg ] || fail "through the view: outputs missing"
for t in refind poses4 problem7 own function log10; do
  diff -r "fixed/out_$t" "view/out_$t" > /dev/null || fail "$t: the output files differ between the view and the per-model program"
  cmp -s "fixed/$t.out" "view/$t.out" || fail "$t: the standard output differs between the view and the per-model program"
  cmp -s "fixed/$t.err.tool" "view/$t.err.tool" || fail "$t: the standard error differs between the view and the per-model program"
done
ok "the model view: path, motion, exact synthesis and function generation, no per-model program, the per-model program's bytes"

[ "$failures" = 0 ] && echo "all passed" || echo "$failures failure(s)"
exit $((failures > 0))
