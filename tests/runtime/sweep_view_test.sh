#!/usr/bin/env bash
# mechgen_view sweep (issue 43): a model compiled into a shared object with its view's entry
# point (<name>.cc + <name>_view.cc, -DMECHGEN_VIEW_ENTRY, g++ -O2 -shared -fPIC), loaded and
# swept through the runtime compiled once (mechgen_runtime_view):
#  - its CSV and SVG equal, byte for byte, the per-model tool's (<name>_sweep) for the same
#    options, and so do its printed summary and the parameters' error messages;
#  - an object without the entry point, a missing object and an option the view does not take
#    yet are refused (exit 1, 1, 2) with one line on stderr and nothing written.
# usage: sweep_view_test.sh <c++ compiler> <mechgen_view> <fourbar_sweep> <model dir>
#        <runtime include dir> <Eigen include dir>
set -uo pipefail
cxx=$1 view_tool=$(realpath "$2") fixed_tool=$(realpath "$3") model_dir=$4 runtime_include=$5 eigen=$6
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cd "$root" || exit 1

"$cxx" -O2 -shared -fPIC -DMECHGEN_VIEW_ENTRY -I"$model_dir" -I"$runtime_include" -I"$eigen" \
  "$model_dir/fourbar.cc" "$model_dir/fourbar_view.cc" -o fourbar.so || { echo "FAIL: cannot build fourbar.so"; exit 1; }
"$cxx" -O2 -shared -fPIC -I"$model_dir" -I"$runtime_include" -I"$eigen" \
  "$model_dir/fourbar.cc" "$model_dir/fourbar_view.cc" -o no_entry.so || { echo "FAIL: cannot build no_entry.so"; exit 1; }

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
refused design 2 "^fourbar_sweep_view: error: --design: the design derivatives are not reached through the model view" "$root/fourbar.so" --design
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
# run by mechgen (MECHGEN_VIEW_FALLBACK=1), what the view lacks is exit 120 and nothing said or
# written: mechgen then runs the per-model program
mkdir fallback && (cd fallback && MECHGEN_VIEW_FALLBACK=1 "$view_tool" sweep "$root/fourbar.so" --design --csv out.csv > ../fallback.out 2> ../fallback.err)
status=$?
[[ $status -eq 120 ]] || fail "fallback: exit $status, expected 120"
[[ ! -s fallback.out && ! -s fallback.err ]] || fail "fallback: said $(cat fallback.out fallback.err)"
[[ -z $(ls -A fallback) ]] || fail "fallback: wrote $(ls -A fallback)"
# the command first: an unknown one is a usage error before anything is loaded
mkdir no_command && (cd no_command && "$view_tool" no-such-command "$root/fourbar.so" > ../no_command.out 2> ../no_command.err)
status=$?
[[ $status -eq 2 ]] || fail "no_command: exit $status, expected 2"
grep -q "^mechgen_view: error: unknown command no-such-command" no_command.err || fail "no_command: $(cat no_command.err)"

[[ $failures -eq 0 ]] && echo "mechgen_view sweep: all checks passed"
exit $((failures > 0))
