#!/usr/bin/env bash
# Issue 24: every shipped model gets every tool its quantities allow, and what a model has is
# what the generator says (cmake/MechgenAddModel.cmake reads no YAML).
# usage: model_tools_test.sh <mechgen> <source dir> <models binary dir> <models,...> \
#                            <model>:<tool>:<program>:<left out 0|1>:<manifest macro> ...
# For each shipped model: `mechgen generate --print-tools` lists the tools its quantities
# allow (sweep, synthesize, study always; statics and flywheel with forces; simulate and
# engine with dynamics); its quantities from `mechgen generate --print-quantities`; the tool
# <model>_<tool> runs as the real tool (`--help` exits 0 and prints its usage) exactly when
# the quantities allow it (sweep: always; statics: forces; simulate: dynamics; engine: the
# engine models, with dynamics), else it is the stub (exit 2, "generated without", naming the
# quantity to add). Independently of --print-quantities, the generated header of the build
# (<models binary dir>/mechgen_<model>/<model>.h) must hold EvalStatics exactly when the
# printed quantities hold forces, and EvalDynamics exactly when they hold dynamics; the
# models of the issue (fivebar_robot, fourbar_balanced: dynamics and shaking imply forces)
# must have a real statics tool; the printed list implies what the reader documents
# (dynamics brings K, L, forces, potential; shaking brings dynamics). A tool left out of the
# build (the test command builds only the tools some test runs) is not run: the macro of the
# model's manifest (<models binary dir>/mechgen_<model>/<model>_manifest.h) that its `#if`
# reads must be 1 exactly when the quantities allow the tool; the sweep has no stub (no `#if`):
# left out, its manifest's MECHGEN_MODEL_TOOL_SWEEP must be 1 (the tests that want a shipped
# model's sweep run it through mechgen_view; of the sweeps only those some test runs are built).
set -uo pipefail
mechgen=$(realpath "$1") source_dir=$(realpath "$2") models_dir=$(realpath "$3") models=$4
shift 4
declare -A program left_out need
for spec in "$@"; do
  IFS=: read -r model tool path out macro <<< "$spec"
  program[$model:$tool]=$path left_out[$model:$tool]=$out need[$model:$tool]=$macro
done
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
has() { [[ " $1 " == *" $2 "* ]]; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

real_tools=0 stubs=0 manifests=0
IFS=, read -r -a shipped <<< "$models"
for model in "${shipped[@]}"; do
  quantities=$("$mechgen" generate "$source_dir/models/$model.yaml" --print-quantities 2> "$work/err")
  status=$?
  if [ "$status" -ne 0 ] || [ -s "$work/err" ]; then
    fail "$model: --print-quantities exit $status: $(cat "$work/err")"
    continue
  fi
  [ "$(printf '%s\n' "$quantities" | grep -c '')" -eq 1 ] || fail "$model: not one line: $quantities"
  # What the reader's implications promise.
  if has "$quantities" shaking && ! has "$quantities" dynamics; then fail "$model: shaking without dynamics"; fi
  if has "$quantities" dynamics; then
    for q in K L forces potential; do has "$quantities" "$q" || fail "$model: dynamics without $q: $quantities"; done
  fi
  # --print-tools (what mechgen_add_model() defines a model's tools from, the driver's one
  # table) gives the tools the quantities allow, by this test's own rule, in the driver's order.
  expected="sweep"
  has "$quantities" forces && expected+=" statics"
  has "$quantities" dynamics && expected+=" simulate engine"
  has "$quantities" forces && expected+=" flywheel"
  expected+=" synthesize study"
  printed=$("$mechgen" generate "$source_dir/models/$model.yaml" --print-tools 2> "$work/err")
  [ $? -eq 0 ] && [ ! -s "$work/err" ] && [ "$printed" = "$expected" ] ||
    fail "$model: --print-tools '$printed', expected '$expected' (quantities: $quantities): $(cat "$work/err")"
  # The generated code agrees (a second witness of what the model has).
  header="$models_dir/mechgen_$model/$model.h"
  if [ -f "$header" ]; then
    grep -q "^void EvalStatics(" "$header" && statics_code=1 || statics_code=0
    grep -q "^void EvalDynamics(" "$header" && dynamics_code=1 || dynamics_code=0
    has "$quantities" forces && want=1 || want=0
    [ "$statics_code" -eq "$want" ] || fail "$model: EvalStatics in the header: $statics_code, forces listed: $want"
    has "$quantities" dynamics && want=1 || want=0
    [ "$dynamics_code" -eq "$want" ] || fail "$model: EvalDynamics in the header: $dynamics_code, dynamics listed: $want"
  else
    fail "$model: no generated header $header"
  fi
  for tool in sweep statics simulate engine; do
    case $tool in
      sweep) allowed=1 quantity="" ;;
      statics) has "$quantities" forces && allowed=1 || allowed=0; quantity=forces ;;
      simulate) has "$quantities" dynamics && allowed=1 || allowed=0; quantity=dynamics ;;
      engine)
        # Only the engine models (tools/make_engine.py) are given ENGINE; they have dynamics.
        [[ $model == engine_* ]] || continue
        has "$quantities" dynamics && allowed=1 || allowed=0; quantity=dynamics ;;
    esac
    path=${program[$model:$tool]:-}
    if [ -z "$path" ]; then
      fail "$model: no ${model}_$tool tool (quantities: $quantities)"
      continue
    fi
    if [ "${left_out[$model:$tool]}" = 1 ]; then
      manifest="$models_dir/mechgen_$model/${model}_manifest.h"
      macro=${need[$model:$tool]}
      [ "$tool" = sweep ] && macro=MECHGEN_MODEL_TOOL_SWEEP
      if [ -z "$macro" ]; then
        fail "${model}_$tool is left out of the build and has no manifest macro to check"
      elif ! value=$(grep -oP "^#define $macro \K[01]$" "$manifest"); then
        fail "${model}_$tool: no '#define $macro 0|1' in $manifest"
      elif [ "$value" -ne "$allowed" ]; then
        fail "${model}_$tool: $macro is $value in the manifest, the quantities say $allowed ($quantities)"
      else
        manifests=$((manifests + 1))
      fi
      continue
    fi
    "$path" --help > "$work/out" 2> "$work/err" < /dev/null
    status=$?
    if [ "$allowed" -eq 1 ]; then
      if [ "$status" -ne 0 ] || [ ! -s "$work/out" ] || grep -q "generated without" "$work/out" "$work/err"; then
        fail "${model}_$tool should be the real tool (quantities: $quantities): exit $status, $(head -c 300 "$work/err")"
      else
        real_tools=$((real_tools + 1))
      fi
    else
      if [ "$status" -ne 2 ] || ! grep -q "^error: the model '$model' was generated without .*add \`$quantity\`" "$work/err" ||
         [ "$(grep -c '' "$work/err")" -ne 1 ] || [ -s "$work/out" ]; then
        fail "${model}_$tool should be the stub (quantities: $quantities): exit $status, stderr $(head -c 300 "$work/err")"
      else
        stubs=$((stubs + 1))
      fi
    fi
  done
done

# The models the issue names: their quantities imply forces, so they have a statics tool.
for model in fivebar_robot fourbar_balanced; do
  path=${program[$model:statics]:-}
  if [ -z "$path" ]; then
    fail "$model has no statics tool"
  elif [ "${left_out[$model:statics]}" = 1 ]; then
    grep -q "^#define MECHGEN_MODEL_HAS_FORCES 1$" "$models_dir/mechgen_$model/${model}_manifest.h" ||
      fail "${model}_statics (left out of the build): its manifest says no forces"
  else
    "$path" --help > "$work/out" 2>&1 || fail "${model}_statics --help: exit $?: $(head -c 300 "$work/out")"
  fi
done
# --print-quantities writes nothing, and refuses a bad model with the reader's located line.
(cd "$work" && "$mechgen" generate "$source_dir/models/fourbar.yaml" --print-quantities > q.txt) ||
  fail "--print-quantities on fourbar"
[ "$(cat "$work/q.txt")" = "K L scene" ] || fail "fourbar: $(cat "$work/q.txt"), expected 'K L scene'"
[ "$(ls "$work")" = "err
out
q.txt" ] || fail "--print-quantities wrote files: $(ls "$work")"
printf 'name: x\noutputs:\n  quantities: [K, speed]\n' > "$work/bad.yaml"
"$mechgen" generate "$work/bad.yaml" --print-quantities > "$work/out" 2> "$work/err"
status=$?
{ [ "$status" -eq 1 ] && [ ! -s "$work/out" ] && grep -q "^$work/bad.yaml:[0-9]*:[0-9]*: error: " "$work/err"; } ||
  fail "a bad model: exit $status, $(cat "$work/err")"

echo "$real_tools real tools and $stubs stubs run, $manifests left out of the build checked by their manifest," \
  "as the quantities say; $failures failure(s)"
exit $((failures > 0))
