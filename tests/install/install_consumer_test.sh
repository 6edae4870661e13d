#!/usr/bin/env bash
# Installs mechgen from the build tree into a temporary prefix, then configures, builds
# and runs two consumer projects that use find_package(mechgen) and mechgen_add_model:
#   consumer/           the generated four-bar alone (Ceres findable), and the tools
#                       mechgen_add_model defines for two models as their quantities say
#                       (asked of the installed mechgen at configure time; issue 24);
#   consumer_no_ceres/  the generated four-bar and the Ceres-free runtime, configured with
#                       Ceres made unfindable (find_package(mechgen) must still succeed).
# Then the installed `mechgen sweep` on a copy of the four-bar in a directory outside the
# source tree: it must compile against the installed runtime headers and driver (not the
# source tree's), write the CSV, and run from its cache the second time.
set -euo pipefail
build_dir=$(cd "$1" && pwd) source_dir=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
test -x "$work/prefix/bin/mechgen"
test -f "$work/prefix/lib/cmake/mechgen/mechgenConfig.cmake"
cmake -S "$source_dir/tests/install/consumer" -B "$work/build" -G Ninja \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DMODEL_FILE="$source_dir/models/fourbar.yaml" > "$work/configure.log"
cmake --build "$work/build" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
"$work/build/consumer"
cmake -S "$source_dir/tests/install/consumer_no_ceres" -B "$work/build_no_ceres" -G Ninja \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DMODEL_FILE="$source_dir/models/fourbar.yaml" \
  -DCMAKE_DISABLE_FIND_PACKAGE_Ceres=ON -DCeres_DIR=/nonexistent \
  > "$work/configure_no_ceres.log" || { cat "$work/configure_no_ceres.log"; exit 1; }
cmake --build "$work/build_no_ceres" > "$work/build_no_ceres.log" || { cat "$work/build_no_ceres.log"; exit 1; }
"$work/build_no_ceres/consumer_no_ceres"

# `mechgen sweep` from the installed tree, in a directory that is not the source tree.
mkdir "$work/outside"
cp "$source_dir/models/fourbar.yaml" "$work/outside/my_fourbar.yaml"
cd "$work/outside"
export MECHGEN_CACHE_DIR="$work/cache"
"$work/prefix/bin/mechgen" sweep --verbose my_fourbar.yaml --steps 36 --csv out.csv --table 3 \
  > sweep.out 2> sweep.err || { cat sweep.err; exit 1; }
grep -q -- "-I$work/prefix/include " sweep.err || { echo "not the installed headers:"; cat sweep.err; exit 1; }
# the runtime compiled once, installed beside mechgen, runs the model's object
grep -q -- "^mechgen: $work/prefix/bin/mechgen_view --name " sweep.err || { echo "not the installed mechgen_view:"; cat sweep.err; exit 1; }
if grep -q -- "$source_dir/runtime" sweep.err; then echo "used the source tree:"; cat sweep.err; exit 1; fi
# the per-model program (MECHGEN_VIEW=0) from the installed driver
MECHGEN_VIEW=0 "$work/prefix/bin/mechgen" sweep --verbose my_fourbar.yaml --steps 36 --csv per_model.csv --table 3 \
  > per_model.out 2> per_model.err || { cat per_model.err; exit 1; }
grep -q -- " $work/prefix/share/mechgen/tools/sweep_main.cc " per_model.err || { echo "not the installed driver:"; cat per_model.err; exit 1; }
if grep -q -- "$source_dir/runtime" per_model.err; then echo "used the source tree:"; cat per_model.err; exit 1; fi
cmp out.csv per_model.csv || { echo "the two routes' CSVs differ"; exit 1; }
[ "$(grep -vc '^#' out.csv)" -eq 38 ] || { echo "out.csv: $(grep -vc '^#' out.csv) lines, expected 38"; exit 1; }
grep -q "^37/37 configurations converged" sweep.out || { cat sweep.out; exit 1; }
"$work/prefix/bin/mechgen" sweep my_fourbar.yaml --steps 36 --csv again.csv > again.out 2> again.err ||
  { cat again.err; exit 1; }
[ ! -s again.err ] || { echo "second run compiled again:"; cat again.err; exit 1; }
cmp out.csv again.csv
echo "installed mechgen sweep: ok"
