#!/usr/bin/env bash
# Installs mechgen from the build tree into a temporary prefix, then configures, builds
# and runs a consumer project that uses find_package(mechgen) and mechgen_add_model.
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
