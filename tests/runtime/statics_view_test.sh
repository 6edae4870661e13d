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
#  - an option the view does not take yet (--design) and a bad --set are refused (exit 2)
#    with one line on stderr and nothing written; run by mechgen (MECHGEN_VIEW_FALLBACK=1) what
#    the view lacks is exit 120 with nothing said or written.
# usage: statics_view_test.sh <c++ compiler> <mechgen_view> <models dir> <runtime include dir>
#        <Eigen include dir> <slider_crank_friction_statics> <fourbar_loaded_statics>
set -uo pipefail
cxx=$1 view_tool=$(realpath "$2") models=$3 runtime_include=$4 eigen=$5
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
declare -A fixed_tool=([slider_crank_friction]=$(realpath "$6") [fourbar_loaded]=$(realpath "$7"))
cd "$root" || exit 1

for model in slider_crank_friction fourbar_loaded; do
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
refused design "^fourbar_loaded_statics_view: error: --design: " "$root/fourbar_loaded.so" --csv out.csv --design
refused set "^slider_crank_friction_statics_view: error: --set 'nosuch=1': no parameter 'nosuch' in the model" \
  "$root/slider_crank_friction.so" --csv out.csv --set nosuch=1
# run by mechgen (MECHGEN_VIEW_FALLBACK=1), what the view lacks is exit 120, nothing said or written
mkdir fallback && (cd fallback && MECHGEN_VIEW_FALLBACK=1 "$view_tool" statics "$root/fourbar_loaded.so" \
  --csv out.csv --design > ../fallback.out 2> ../fallback.err)
status=$?
[[ $status -eq 120 ]] || fail "fallback: exit $status, expected 120"
[[ ! -s fallback.out && ! -s fallback.err && -z $(ls -A fallback) ]] || fail "fallback: said or wrote something"
refused bad_option "^slider_crank_friction_statics_view: error: " "$root/slider_crank_friction.so" --no-such-option

[[ $failures -eq 0 ]] && echo "mechgen_view statics: all checks passed"
exit $((failures > 0))
