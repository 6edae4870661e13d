#!/usr/bin/env bash
# mechgen_view statics (issue 43): models compiled into shared objects with their view's entry
# point (<name>.cc + <name>_view.cc, -DMECHGEN_VIEW_ENTRY, g++ -O2 -shared -fPIC), loaded and
# run through the statics of the runtime compiled once (mechgen_runtime_view):
#  - the CSV equals, byte for byte, the per-model tool's (<name>_statics) for the same options:
#    a slider-crank with Coulomb friction (forward and backward drives, its dead zones and
#    equilibria) and a loaded four-bar (springs, gravity, stiffness), at rest and at --speed;
#  - the printed output equals the per-model tool's but for the timing figure (us/row), the
#    CSV's name and the wrote line's path;
#  - --set and --params through the view's parameter table: the same CSV and summary;
#  - the SVG (the force diagram) equals the per-model tool's, byte for byte;
#  - --design (the statics' design derivatives through the view's Design and StaticsDesign):
#    the CSV, stdout (the timing aside) and stderr equal the per-model tool's for two models
#    with a design section, the loaded four-bar and the single-cylinder engine (whose loads
#    read a velocity: --design with --speed is its usage error, through both);
#  - --design on a model without a design section and a bad --set are refused (exit 2) with
#    one line on stderr and nothing written, run by mechgen (MECHGEN_VIEW_FALLBACK=1) too: the
#    statics have nothing left to fall back for.
# usage: statics_view_test.sh <c++ compiler> <mechgen_view> <models dir> <runtime include dir>
#        <Eigen include dir> <slider_crank_friction_statics> <fourbar_loaded_statics>
#        <engine_single_statics>
set -uo pipefail
cxx=$1 view_tool=$(realpath "$2") models=$3 runtime_include=$4 eigen=$5
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
declare -A fixed_tool=([slider_crank_friction]=$(realpath "$6") [fourbar_loaded]=$(realpath "$7")
                       [engine_single]=$(realpath "$8"))
cd "$root" || exit 1

for model in slider_crank_friction fourbar_loaded engine_single; do
  dir=$models/mechgen_$model
  "$cxx" -O2 -shared -fPIC -DMECHGEN_VIEW_ENTRY -I"$dir" -I"$runtime_include" -I"$eigen" \
    "$dir/$model.cc" "$dir/${model}_view.cc" -o "$model.so" || { echo "FAIL: cannot build $model.so"; exit 1; }
done

# The timing figure and the CSV's path are the only differences the printed output may have.
normalize() { sed -e 's/[0-9.]* us\/row/T us\/row/' -e 's/^wrote [^ ]*\.csv /wrote CSV /' "$1"; }
same() {  # same <model> <options...>
  local model=$1
  shift
  "${fixed_tool[$model]}" "$@" --csv fixed.csv > fixed.out 2> fixed.err || fail "${model}_statics $*: $(cat fixed.err)"
  "$view_tool" statics "./$model.so" "$@" --csv view.csv > view.out 2> view.err ||
    fail "mechgen_view statics $model $*: $(cat view.err)"
  [[ $(wc -l < fixed.csv) -gt 20 ]] || fail "$model $*: the CSV has $(wc -l < fixed.csv) lines"
  cmp -s fixed.csv view.csv || fail "$model $*: the CSVs differ: $(diff fixed.csv view.csv | head -4)"
  diff <(normalize fixed.out) <(normalize view.out) > /dev/null ||
    fail "$model $*: the outputs differ: $(diff <(normalize fixed.out) <(normalize view.out) | head -6)"
  [[ -s view.err ]] && fail "$model $*: stderr not empty: $(cat view.err)"
  rm -f fixed.csv view.csv
}
same slider_crank_friction --steps 180 --dead-zones --equilibria --samples 72
same slider_crank_friction --steps 90 --speed 60rpm --range theta_crank:10deg:300deg
same fourbar_loaded --equilibria --samples 90
same fourbar_loaded --steps 120 --speed -2.5 --table 3
# the parameters through the view's table (common/view_params.h): the same numbers and summary
printf 'mu_O = 0.25  # the crank bearing\nr_O: 0.04\n' > friction.params
same slider_crank_friction --steps 90 --set F=1500 --set mu_s=0.3 --dead-zones
same slider_crank_friction --steps 90 --params friction.params --set b=0.4

# --design: the design columns (and the rest) byte for byte, stdout and stderr as the tool's.
# same_design <model> <case> <expected status> <options...>
same_design() {
  local model=$1 name=$2 expected=$3
  shift 3
  mkdir -p "$name/fixed" "$name/view"
  (cd "$name/fixed" && "${fixed_tool[$model]}" --design "$@" --csv out.csv > ../fixed.out 2> ../fixed.err)
  local fixed_status=$?
  (cd "$name/view" && "$view_tool" --name "${model}_statics" statics "$root/$model.so" --design "$@" --csv out.csv \
    > ../view.out 2> ../view.err)
  local view_status=$?
  [[ $fixed_status -eq $expected ]] || fail "$name: ${model}_statics exited $fixed_status: $(head -3 "$name/fixed.err")"
  [[ $view_status -eq $fixed_status ]] || fail "$name: the view exited $view_status: $(head -3 "$name/view.err")"
  if [[ $expected -eq 0 ]]; then
    [[ $(grep -v '^#' "$name/fixed/out.csv" | head -1 | tr ',' '\n' | grep -c '/d') -gt 5 ]] ||
      fail "$name: no design columns in the tool's CSV"
  fi
  diff -r "$name/fixed" "$name/view" > /dev/null || fail "$name: the files differ: $(diff -r "$name/fixed" "$name/view" | head -4)"
  diff <(normalize "$name/fixed.out") <(normalize "$name/view.out") > /dev/null ||
    fail "$name: stdout differs: $(diff <(normalize "$name/fixed.out") <(normalize "$name/view.out") | head -6)"
  cmp -s "$name/fixed.err" "$name/view.err" || fail "$name: stderr differs: $(diff "$name/fixed.err" "$name/view.err" | head -4)"
}
same_design fourbar_loaded design_fourbar_loaded 0 --table 3
same_design fourbar_loaded design_fourbar_loaded_scans 0 --equilibria --samples 90 --set k=120 --steps 120
same_design fourbar_loaded design_fourbar_loaded_speed 0 --speed -2.5 --steps 100  # (nothing there reads a speed)
same_design engine_single design_engine_single 0 --table 3 --dead-zones
same_design engine_single design_engine_single_set 0 --set r=0.05 --set m_pis=0.6 --steps 180 --equilibria
same_design engine_single design_engine_single_speed 2 --speed 3000rpm
grep -q "^engine_single_statics: error: --design with --speed" design_engine_single_speed/view.err ||
  fail "design_engine_single_speed: $(cat design_engine_single_speed/view.err)"

# refused <name> <pattern> <args...>: exit status 2, one stderr line, nothing written.
refused() {
  local name=$1 pattern=$2
  shift 2
  mkdir "$name" && (cd "$name" && "$view_tool" statics "$@" > ../"$name".out 2> ../"$name".err)
  local status=$?
  [[ $status -eq 2 ]] || fail "$name: exit $status, expected 2"
  [[ $(wc -l < "$name".err) -eq 1 ]] || fail "$name: stderr is not one line: $(cat "$name".err)"
  grep -Eq "$pattern" "$name".err || fail "$name: stderr $(cat "$name".err) does not match $pattern"
  [[ -z $(ls -A "$name") ]] || fail "$name: wrote $(ls -A "$name")"
}
# the force diagram (statics/svg.h reads the view's description): the per-model tool's bytes
for model in slider_crank_friction fourbar_loaded; do
  "${fixed_tool[$model]}" --steps 72 --table 0 --svg fixed.svg > /dev/null 2>&1 || fail "${model}_statics --svg"
  "$view_tool" statics "./$model.so" --steps 72 --table 0 --svg view.svg > /dev/null 2> view.err || fail "view --svg: $(cat view.err)"
  cmp -s fixed.svg view.svg || fail "$model: the SVGs differ"
  rm -f fixed.svg view.svg
done
refused no_design "^slider_crank_friction_statics_view: error: --design: the model slider_crank_friction has no design section" \
  "$root/slider_crank_friction.so" --csv out.csv --design
MECHGEN_VIEW_FALLBACK=1 refused no_design_fallback "^slider_crank_friction_statics_view: error: --design: the model" \
  "$root/slider_crank_friction.so" --csv out.csv --design
refused set "^slider_crank_friction_statics_view: error: --set 'nosuch=1': no parameter 'nosuch' in the model" \
  "$root/slider_crank_friction.so" --csv out.csv --set nosuch=1
refused bad_option "^slider_crank_friction_statics_view: error: " "$root/slider_crank_friction.so" --no-such-option

[[ $failures -eq 0 ]] && echo "mechgen_view statics: all checks passed"
exit $((failures > 0))
