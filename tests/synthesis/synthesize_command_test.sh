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
#   - four poses of the shipped four-bar's coupler (hand formulas): curves.csv and curves.svg.
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

[ "$failures" = 0 ] && echo "all passed" || echo "$failures failure(s)"
exit $((failures > 0))
