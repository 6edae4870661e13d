#!/usr/bin/env bash
# Installs mechgen from the build tree into a temporary prefix, then configures, builds
# and runs two consumer projects that use find_package(mechgen) and mechgen_add_model:
#   consumer/           the generated four-bar alone (Ceres findable);
#   consumer_no_ceres/  the generated four-bar and the Ceres-free runtime, configured with
#                       Ceres made unfindable (find_package(mechgen) must still succeed).
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
