#!/usr/bin/env bash
# mechgen_view sweep (issue 43): a model compiled into a shared object with its view's entry
# point (<name>.cc + <name>_view.cc, -DMECHGEN_VIEW_ENTRY, g++ -O2 -shared -fPIC), loaded and
# swept through the runtime compiled once (mechgen_runtime_view):
#  - its CSV and SVG equal, byte for byte, the per-model tool's (<name>_sweep) for the same
#    options, and so do its printed summary and the parameters' error messages;
#  - with --design (the design derivatives through the view's Design), the CSV, stdout and
#    stderr equal the per-model tool's, byte for byte, for two models with a design section
#    (the four-bar and the slider-crank), a non-Grashof four-bar turned back at its dead points
#    among them;
#  - an object without the entry point, a missing object, --design on a model without a design
#    section and a bad option are refused (exit 1, 1, 2, 2) with one line on stderr and nothing
#    written.
# usage: sweep_view_test.sh <c++ compiler> <mechgen_view> <fourbar_sweep> <model dir>
#        <runtime include dir> <Eigen include dir> <slider_crank_sweep> <slider_crank model dir>
#        <a model dir without a design section: quick_return>
set -uo pipefail
cxx=$1 view_tool=$(realpath "$2") fixed_tool=$(realpath "$3") model_dir=$4 runtime_include=$5 eigen=$6
slider_crank_tool=$(realpath "$7") slider_crank_dir=$8 no_design_dir=$9
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cd "$root" || exit 1

"$cxx" -O2 -shared -fPIC -DMECHGEN_VIEW_ENTRY -I"$model_dir" -I"$runtime_include" -I"$eigen" \
  "$model_dir/fourbar.cc" "$model_dir/fourbar_view.cc" -o fourbar.so || { echo "FAIL: cannot build fourbar.so"; exit 1; }
"$cxx" -O2 -shared -fPIC -I"$model_dir" -I"$runtime_include" -I"$eigen" \
  "$model_dir/fourbar.cc" "$model_dir/fourbar_view.cc" -o no_entry.so || { echo "FAIL: cannot build no_entry.so"; exit 1; }
"$cxx" -O2 -shared -fPIC -DMECHGEN_VIEW_ENTRY -I"$slider_crank_dir" -I"$runtime_include" -I"$eigen" \
  "$slider_crank_dir/slider_crank.cc" "$slider_crank_dir/slider_crank_view.cc" -o slider_crank.so ||
  { echo "FAIL: cannot build slider_crank.so"; exit 1; }
"$cxx" -O2 -shared -fPIC -DMECHGEN_VIEW_ENTRY -I"$no_design_dir" -I"$runtime_include" -I"$eigen" \
  "$no_design_dir/quick_return.cc" "$no_design_dir/quick_return_view.cc" -o quick_return.so ||
  { echo "FAIL: cannot build quick_return.so"; exit 1; }

printf 'b = 3.4  # the coupler\nxi: 1.2\n' > params.txt
for options in "" "--steps 100 --range theta_crank:-30deg:400deg --qd 2 --qdd -1" \
  "--set b=3.6 --set eta=0.5" "--params params.txt --set xi=1.3 --steps 90"; do
  # shellcheck disable=SC2086
  "$fixed_tool" $options --table 0 --csv fixed.csv > fixed.out || fail "fourbar_sweep $options"
  # shellcheck disable=SC2086
  "$view_tool" sweep ./fourbar.so $options --table 0 --csv view.csv > view.out 2> view.err || fail "mechgen_view sweep $options: $(cat view.err)"
  cmp -s fixed.csv view.csv || fail "the CSVs differ ($options)"
  # the drawing: io/svg.h reads the view's drawing description
  # shellcheck disable=SC2086
  "$fixed_tool" $options --table 0 --svg fixed.svg --no-animation > /dev/null || fail "fourbar_sweep --svg $options"
  # shellcheck disable=SC2086
  "$view_tool" sweep ./fourbar.so $options --table 0 --svg view.svg --no-animation > /dev/null 2> view.err || fail "mechgen_view sweep --svg $options: $(cat view.err)"
  cmp -s fixed.svg view.svg || fail "the SVGs differ ($options)"
  rm -f fixed.svg view.svg
  # the printed summary too (the parameters set among it), but for the timings
  summary() { sed -e '/time per row/d' -e '/ s)/d' -e '/steps\/s/d' -e 's/\(fixed\|view\)\.csv/OUT.csv/' "$1"; }
  diff <(summary fixed.out) <(summary view.out) > /dev/null ||
    fail "the printed summaries differ ($options): $(diff fixed.out view.out | head -5)"
  [[ -s view.err ]] && fail "stderr not empty: $(cat view.err)"
  rm -f fixed.csv view.csv
done

# --design: the design columns through the view's Design. same_design <tool> <object> <case>
# <expected status> <options...>: CSV, stdout (the timing line aside) and stderr byte for byte.
same_design() {
  local tool=$1 object=$2 name=$3 expected=$4
  shift 4
  mkdir -p "$name/fixed" "$name/view"
  (cd "$name/fixed" && "$tool" --design "$@" --csv out.csv > ../fixed.out 2> ../fixed.err)
  local fixed_status=$?
  (cd "$name/view" && "$view_tool" --name "$(basename "$tool")" sweep "$object" --design "$@" --csv out.csv \
    > ../view.out 2> ../view.err)
  local view_status=$?
  [[ $fixed_status -eq $expected ]] || fail "$name: the tool exited $fixed_status: $(head -3 "$name/fixed.err")"
  [[ $view_status -eq $fixed_status ]] || fail "$name: the view exited $view_status: $(head -3 "$name/view.err")"
  [[ $(head -200 "$name/fixed/out.csv" | grep -v '^#' | head -1 | tr ',' '\n' | grep -c '/d') -gt 10 ]] ||
    fail "$name: no design columns in the tool's CSV"
  cmp -s "$name/fixed/out.csv" "$name/view/out.csv" ||
    fail "$name: the CSVs differ: $(diff "$name/fixed/out.csv" "$name/view/out.csv" | head -4)"
  diff <(sed '/time per row/d' "$name/fixed.out") <(sed '/time per row/d' "$name/view.out") > /dev/null ||
    fail "$name: stdout differs: $(diff "$name/fixed.out" "$name/view.out" | head -6)"
  cmp -s "$name/fixed.err" "$name/view.err" || fail "$name: stderr differs: $(diff "$name/fixed.err" "$name/view.err" | head -4)"
}
same_design "$fixed_tool" "$root/fourbar.so" design_fourbar 0 --table 4
same_design "$fixed_tool" "$root/fourbar.so" design_fourbar_range 0 --steps 90 --range theta_crank:-30deg:200deg \
  --qd 2 --set b=3.6 --set eta=0.5 --table 0
# a non-Grashof four-bar, its crank turned back at the dead points (--at-singular reverse). (Where
# the sweep stops there instead, the step that finds the dead point falls back to the assembler,
# Ceres in the tool and the runtime's Levenberg-Marquardt through the view: their iterations
# differ, so that case, with its rows of NaN derivatives, is compared in model_test, both on the
# runtime's assembler: view_solver_test.cc.)
same_design "$fixed_tool" "$root/fourbar.so" design_fourbar_reverse 0 --set a=2.8 --at-singular reverse --steps 150
same_design "$slider_crank_tool" "$root/slider_crank.so" design_slider_crank 0 --table 3
same_design "$slider_crank_tool" "$root/slider_crank.so" design_slider_crank_range 0 --steps 77 --qd 3 --qdd -1 --table 0

# refused <name> <status> <pattern> <args...>: exit status, one stderr line, nothing written.
refused() {
  local name=$1 expected=$2 pattern=$3
  shift 3
  mkdir "$name" && (cd "$name" && "$view_tool" sweep "$@" > ../"$name".out 2> ../"$name".err)
  local status=$?
  [[ $status -eq $expected ]] || fail "$name: exit $status, expected $expected"
  [[ $(wc -l < "$name".err) -eq 1 ]] || fail "$name: stderr is not one line: $(cat "$name".err)"
  grep -Eq "$pattern" "$name".err || fail "$name: stderr $(cat "$name".err) does not match $pattern"
  [[ -z $(ls -A "$name") ]] || fail "$name: wrote $(ls -A "$name")"
}
refused no_entry 1 "has no mechgen_model_view\(\)" "$root/no_entry.so" --csv out.csv
refused missing 1 "^error: cannot load" "$root/missing.so" --csv out.csv
refused no_design 2 "^quick_return_sweep_view: error: --design: the model quick_return has no design section" \
  "$root/quick_return.so" --design --csv out.csv
refused bad_option 2 "^fourbar_sweep_view: error: " "$root/fourbar.so" --no-such-option
# the parameters' errors: the per-model tool's words (exit 2, one line)
for bad in "--set nosuch=1" "--set b" "--set b=abc" "--params missing.txt"; do
  # shellcheck disable=SC2086
  "$fixed_tool" $bad > /dev/null 2> fixed.err; fixed_status=$?
  # shellcheck disable=SC2086
  "$view_tool" sweep ./fourbar.so $bad > /dev/null 2> view.err; view_status=$?
  [[ $fixed_status -eq 2 && $view_status -eq 2 ]] || fail "$bad: exit $fixed_status (fixed), $view_status (view)"
  [[ "$(sed 's/^fourbar_sweep_view:/fourbar_sweep:/' view.err)" == "$(cat fixed.err)" ]] ||
    fail "$bad: the view says $(cat view.err), the tool $(cat fixed.err)"
done
# run by mechgen (MECHGEN_VIEW_FALLBACK=1), the sweep has nothing left to fall back for: --design
# goes through the view (the CSV written), and a model without a design section is the per-model
# tool's usage error (exit 2, its message), not the fallback's exit 120
mkdir fallback && (cd fallback && MECHGEN_VIEW_FALLBACK=1 "$view_tool" sweep "$root/fourbar.so" --design --csv out.csv > ../fallback.out 2> ../fallback.err)
status=$?
[[ $status -eq 0 && -s fallback/out.csv ]] || fail "fallback: exit $status, $(cat fallback.err)"
mkdir fallback_no_design && (cd fallback_no_design && MECHGEN_VIEW_FALLBACK=1 "$view_tool" sweep "$root/quick_return.so" \
  --design --csv out.csv > ../fallback_no_design.out 2> ../fallback_no_design.err)
status=$?
[[ $status -eq 2 ]] || fail "fallback_no_design: exit $status, expected 2"
grep -q "has no design section" fallback_no_design.err || fail "fallback_no_design: $(cat fallback_no_design.err)"
[[ -z $(ls -A fallback_no_design) ]] || fail "fallback_no_design: wrote $(ls -A fallback_no_design)"
# the command first: an unknown one is a usage error before anything is loaded
mkdir no_command && (cd no_command && "$view_tool" no-such-command "$root/fourbar.so" > ../no_command.out 2> ../no_command.err)
status=$?
[[ $status -eq 2 ]] || fail "no_command: exit $status, expected 2"
grep -q "^mechgen_view: error: unknown command no-such-command" no_command.err || fail "no_command: $(cat no_command.err)"

[[ $failures -eq 0 ]] && echo "mechgen_view sweep: all checks passed"
exit $((failures > 0))
