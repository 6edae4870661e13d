#!/usr/bin/env bash
# `mechgen statics|simulate|engine <model.yaml> [options]` (generator/driver/tool_command.cc),
# each against the <model>_<tool> that mechgen_add_model() builds (the oracle: the same driver
# source compiled by CMake, statics with the Ceres assembler), run in a temporary directory
# outside the source tree on copies of the shipped models, with a private cache.
# usage: tool_commands_test.sh <mechgen> <source dir> <slider_crank_friction_statics>
#                              <slider_crank_motor_simulate> <engine_single_engine>
#                              <mechgen_view> <fourbar_balanced.so>
#   - a model without what the tool needs (fourbar: no `forces`, no `dynamics`): exit 1, one
#     line naming the quantity to add, nothing compiled, no cache entry;
#   - statics (through the runtime compiled once: the model's object in view/): the first run
#     compiles the model (says so), its CSV and SVG are byte-identical to
#     slider_crank_friction_statics' with the same options, stdout too but for the timing
#     line; a second run uses the cache (no "compiling", the program unchanged) and gives the
#     same CSV; a usage error of the driver comes back with its exit status 2; --help works;
#   - simulate: the CSV of the motor start-up byte-identical to slider_crank_motor_simulate's;
#   - engine: the cycle CSV and output byte-identical to engine_single_engine's (through the
#     runtime compiled once: no per-model program built);
#   - parameters at run time: slider_crank_friction_statics with --set a=0.12 --set mu_s=0.3
#     (and the same from a --params file) gives byte for byte the CSV and SVG of `mechgen
#     statics` on a copy of the model with those two values edited by hand; an unknown name
#     (the parameters listed), a derived parameter (fourbar_balanced's sweep --set W2x=...,
#     mechgen_view on the model's shared object: the per-model tool's words), a
#     bad value (also nan, inf, an overflowing number) and a line of a --params file without a
#     value are one-line usage errors
#     (exit 2) naming the fault.
set -uo pipefail
mechgen=$(realpath "$1") source_dir=$(realpath "$2")
statics_tool=$(realpath "$3") simulate_tool=$(realpath "$4") engine_tool=$(realpath "$5")
balanced_sweep=("$(realpath "$6")" sweep "$(realpath "$7")")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
cd "$root" || exit 1
case "$root" in "$source_dir"/*) echo "FAIL: $root is inside the source tree"; exit 1 ;; esac
export MECHGEN_CACHE_DIR=$root/cache
for m in fourbar slider_crank_friction slider_crank_motor engine_single; do
  cp "$source_dir/models/$m.yaml" "$m.yaml"
done
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { echo "ok $*"; }
entries() { find "$MECHGEN_CACHE_DIR/$1" -mindepth 1 -maxdepth 1 -type d ! -name tmp 2>/dev/null | wc -l; }

# A model without the quantity: said before anything is compiled. (The options are answered
# first by the tool's parser where mechgen holds it: the engine's needs its subcommand.)
before=$failures
for tool_quantity in statics:forces simulate:dynamics engine:dynamics; do
  tool=${tool_quantity%%:*} quantity=${tool_quantity#*:}
  extra=()
  [ "$tool" = engine ] && extra=(cycle)
  "$mechgen" "$tool" fourbar.yaml "${extra[@]}" > lack.out 2> lack.err
  status=$?
  [ "$status" -eq 1 ] || fail "$tool on fourbar: exit status $status, expected 1: $(cat lack.err)"
  [ "$(wc -l < lack.err)" -eq 1 ] || fail "$tool on fourbar: expected one line: $(cat lack.err)"
  grep -q "^mechgen: error: the model 'fourbar' (fourbar.yaml) has no \`$quantity\` among its outputs' quantities (it has: K L scene), which \`mechgen $tool\` needs; add \`$quantity\`" lack.err ||
    fail "$tool on fourbar: $(cat lack.err)"
  grep -q compiling lack.err && fail "$tool on fourbar: compiled: $(cat lack.err)"
  [ "$(entries "$tool")" -eq 0 ] || fail "$tool on fourbar: a cache entry was made"
done
[ "$failures" -ne "$before" ] || ok "a model without forces or dynamics: one line, nothing compiled"

# statics against slider_crank_friction_statics.
before=$failures
options=(--steps 72 --table 7 --dead-zones --equilibria)
mkdir -p a b
(cd a && "$mechgen" statics ../slider_crank_friction.yaml "${options[@]}" --csv s.csv --svg s.svg > ../a.out 2> ../a.err)
status=$?
[ "$status" -eq 0 ] || fail "statics: exit status $status: $(cat a.err)"
# through the runtime compiled once: the model alone compiled into the cache's view/ entry
grep -q "^mechgen: compiling the model 'slider_crank_friction' (.*the runtime is compiled once" a.err ||
  fail "statics: no compile message: $(cat a.err)"
(cd b && "$statics_tool" "${options[@]}" --csv s.csv --svg s.svg > ../b.out 2> ../b.err) ||
  fail "slider_crank_friction_statics: $(cat b.err)"
cmp a/s.csv b/s.csv || fail "statics: the CSV differs from slider_crank_friction_statics'"
cmp a/s.svg b/s.svg || fail "statics: the SVG differs from slider_crank_friction_statics'"
[ "$(grep -vc '^#' a/s.csv)" -eq 74 ] || fail "statics: $(grep -vc '^#' a/s.csv) CSV lines, expected 74"
diff <(grep -v 'us/row' a.out) <(grep -v 'us/row' b.out) > stdout.diff ||
  fail "statics: stdout differs: $(head -20 stdout.diff)"
grep -q 'us/row' a.out || fail "statics: no timing line: $(cat a.out)"
program=$(find "$MECHGEN_CACHE_DIR/view" -mindepth 2 -maxdepth 2 -name model.so -type f)
[ "$(printf '%s\n' "$program" | grep -c .)" -eq 1 ] || fail "statics: expected one cached model object: $program"
[ "$failures" -ne "$before" ] || ok "statics: the same CSV, SVG and table as slider_crank_friction_statics"

before=$failures
stamp=$(stat -c %Y.%s "$program")
(cd a && "$mechgen" statics ../slider_crank_friction.yaml "${options[@]}" --csv again.csv > ../c.out 2> ../c.err) ||
  fail "statics, cached: $(cat c.err)"
grep -q compiling c.err && fail "statics, cached: compiled again: $(cat c.err)"
[ "$(stat -c %Y.%s "$program")" = "$stamp" ] || fail "statics, cached: the program changed"
cmp a/again.csv a/s.csv || fail "statics, cached: a different CSV"
"$mechgen" statics slider_crank_friction.yaml --steps 0 > e.out 2> e.err
status=$?
{ [ "$status" -eq 2 ] && grep -q -- '--steps' e.err; } || fail "statics --steps 0: exit status $status: $(cat e.err)"
"$mechgen" statics slider_crank_friction.yaml --help > h.out 2>&1 || fail "statics --help: exit status $?"
grep -q -- '--dead-zones' h.out || fail "statics --help does not list --dead-zones: $(head -5 h.out)"
[ "$(entries view)" -eq 1 ] || fail "statics: expected one cache entry, found $(entries view)"
[ "$(entries statics)" -eq 0 ] || fail "statics: a per-model program was built"
[ "$failures" -ne "$before" ] || ok "statics: cached (no compile), the options reach the driver"

# simulate against slider_crank_motor_simulate (the motor start-up of scripts/quickstart.sh).
before=$failures
options=(--t-end 1 --dt 0.002)
(cd a && "$mechgen" simulate ../slider_crank_motor.yaml "${options[@]}" --csv m.csv > ../sa.out 2> ../sa.err) ||
  fail "simulate: $(cat sa.err)"
(cd b && "$simulate_tool" "${options[@]}" --csv m.csv > ../sb.out 2> ../sb.err) ||
  fail "slider_crank_motor_simulate: $(cat sb.err)"
cmp a/m.csv b/m.csv || fail "simulate: the CSV differs from slider_crank_motor_simulate's"
[ "$(grep -vc '^#' a/m.csv)" -gt 100 ] || fail "simulate: only $(grep -vc '^#' a/m.csv) CSV lines"
[ "$failures" -ne "$before" ] || ok "simulate: the same CSV as slider_crank_motor_simulate"

# engine against engine_single_engine.
before=$failures
options=(cycle --rpm 3000 --samples 360)
(cd a && "$mechgen" engine ../engine_single.yaml "${options[@]}" --csv e.csv > ../ea.out 2> ../ea.err) ||
  fail "engine: $(cat ea.err)"
(cd b && "$engine_tool" "${options[@]}" --csv e.csv > ../eb.out 2> ../eb.err) ||
  fail "engine_single_engine: $(cat eb.err)"
cmp a/e.csv b/e.csv || fail "engine: the cycle CSV differs from engine_single_engine's"
[ "$(grep -vc '^#' a/e.csv)" -gt 300 ] || fail "engine: only $(grep -vc '^#' a/e.csv) CSV lines"
# through the runtime compiled once (mechgen_view engine, issue 43): no per-model program built
[ "$(entries engine)" -eq 0 ] || fail "engine: a per-model program was built ($(entries engine) in engine/)"
cmp -s ea.out eb.out || fail "engine: the output differs from engine_single_engine's: $(diff ea.out eb.out | head -4)"
[ "$failures" -ne "$before" ] || ok "engine: the same cycle CSV and output as engine_single_engine, through the view"
# Parameters at run time against the model edited by hand.
before=$failures
sed -e 's/^  a:    {value: 0.1,/  a:    {value: 0.12,/' -e 's/^  mu_s: {value: 0.15,/  mu_s: {value: 0.3,/' \
  slider_crank_friction.yaml > edited.yaml
[ "$(diff slider_crank_friction.yaml edited.yaml | grep -c '^>')" -eq 2 ] || fail "the edit did not take: $(diff slider_crank_friction.yaml edited.yaml)"
options=(--steps 72 --table 0 --dead-zones)
(cd a && "$mechgen" statics ../edited.yaml "${options[@]}" --csv p.csv --svg p.svg > ../pa.out 2> ../pa.err) ||
  fail "statics on the edited model: $(cat pa.err)"
(cd b && "$statics_tool" "${options[@]}" --set a=0.12 --set mu_s=0.3 --csv p.csv --svg p.svg > ../pb.out 2> ../pb.err) ||
  fail "--set: $(cat pb.err)"
cmp a/p.csv b/p.csv || fail "--set: the CSV differs from the edited model's"
cmp a/p.svg b/p.svg || fail "--set: the SVG differs from the edited model's"
cmp -s a/p.csv a/s.csv && fail "--set: the CSV is the unedited model's"
grep -q '^parameters set: a = 0.12 (default 0.1), mu_s = 0.3 (default 0.15)$' pb.out ||
  fail "--set: no 'parameters set' line: $(head -3 pb.out)"
printf '# the edited values\na = 0.12\n\nmu_s: 0.3  # at the slide\n' > edited.params
(cd b && "$statics_tool" "${options[@]}" --params ../edited.params --csv f.csv > ../pf.out 2> ../pf.err) ||
  fail "--params: $(cat pf.err)"
cmp a/p.csv b/f.csv || fail "--params: the CSV differs from the edited model's"
[ "$failures" -ne "$before" ] || ok "--set and --params: the same bytes as the model edited by hand"

before=$failures
usage() {  # usage <expected text> <command...>: exit status 2, one line containing the text
  local expected=$1
  shift
  "$@" > u.out 2> u.err
  local status=$?
  { [ "$status" -eq 2 ] && [ "$(wc -l < u.err)" -eq 1 ] && grep -qF -- "$expected" u.err; } ||
    fail "$*: exit status $status, expected 2 and '$expected': $(cat u.err)"
}
usage "--set 'radius=1': no parameter 'radius' in the model (parameters: a, b, F, mu_O, r_O, mu_B, r_B, mu_C, r_C, mu_s)" \
  "$statics_tool" --steps 4 --set radius=1
usage "'W2x' is a derived parameter" "${balanced_sweep[@]}" --steps 4 --set W2x=1
usage "--set 'a=big': bad value 'big' for 'a'" "$statics_tool" --steps 4 --set a=big
usage "--set 'a=nan': bad value 'nan' for 'a'" "$statics_tool" --steps 4 --set a=nan
usage "--set 'mu_s=inf': bad value 'inf' for 'mu_s'" "$statics_tool" --steps 4 --set mu_s=inf
usage "--set 'a=1e999': bad value '1e999' for 'a'" "$statics_tool" --steps 4 --set a=1e999
usage "--set 'a': expected name=value" "$statics_tool" --steps 4 --set a
printf 'a = 0.12\nmu_s\n' > bad.params
usage "bad.params:2: expected \`name = value\`, got 'mu_s'" "$statics_tool" --steps 4 --params bad.params
usage "--params: cannot read 'missing.params'" "$statics_tool" --steps 4 --params missing.params
# A NUL byte inside a value or a name (issue 45): the whole text is read, never its part before it.
printf 'a = 1\0005\n' > nul.params
usage "nul.params:1: bad value '1\\x005' for 'a'" "$statics_tool" --steps 4 --params nul.params
printf 'a\000b = 0.12\n' > nulname.params
usage "nulname.params:1: no parameter 'a\\x00b' in the model" "$statics_tool" --steps 4 --params nulname.params
[ "$failures" -ne "$before" ] || ok "--set and --params: bad names, values and files are usage errors"
exit $((failures > 0))
