#!/usr/bin/env bash
# Builds Simbody 3.7 in Release (NDEBUG defined, -O2/-O3) from its source into a prefix outside
# the repository, for the headline comparison of bench/dynamics (Debian's libsimbody-dev 3.7
# is built without NDEBUG: its checks make it ~2x slower). Takes ~15-30 min on two cores.
#
# Usage: bash bench/dynamics/build_simbody_release.sh [prefix] [jobs]
#   prefix  default $HOME/simbody-3.7-release (the install; the build tree is <prefix>-build)
#   jobs    default 2
# Source: SIMBODY_GIT_DIR=<a git dir holding tag Simbody-3.7> (an existing clone or mirror),
# otherwise `git clone --branch Simbody-3.7 https://github.com/simbody/simbody`.
# Then configure mechgen with -DMECHGEN_SIMBODY_RELEASE_DIR=<prefix> and run
# bench/dynamics/run.sh: the benchmark links a second binary, dynamics_bench_simbody_release.
set -euo pipefail
PREFIX=${1:-$HOME/simbody-3.7-release}
JOBS=${2:-2}
TAG=Simbody-3.7
BUILD="$PREFIX-build"
SRC="$BUILD/src"
mkdir -p "$BUILD"
if [ ! -f "$SRC/CMakeLists.txt" ]; then
  rm -rf "$SRC"
  if [ -n "${SIMBODY_GIT_DIR:-}" ]; then
    mkdir -p "$SRC"
    # Without Platform/Windows (BLAS/LAPACK DLLs) and the theory manual's pdf/docx: not
    # needed here, and a partial mirror may not hold their blobs.
    git --git-dir="$SIMBODY_GIT_DIR" ls-tree -r -z --name-only "$TAG" \
      | grep -zvE '^Platform/Windows/|\.(pdf|docx)$' \
      | xargs -0 git --git-dir="$SIMBODY_GIT_DIR" archive "$TAG" -- | tar -x -C "$SRC"
  else
    git clone --depth 1 --branch "$TAG" https://github.com/simbody/simbody "$SRC"
  fi
fi
# Only the libraries: no examples, tests, visualizer or static copies; BLAS/LAPACK found
# by CMake (liblapack-dev, as the Debian package uses). Simbody's own Release flags: -DNDEBUG -O2.
cmake -S "$SRC" -B "$BUILD/obj" -G Ninja \
  -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_INSTALL_PREFIX="$PREFIX" \
  -DCMAKE_INSTALL_LIBDIR=lib \
  -DBUILD_EXAMPLES=OFF -DBUILD_TESTING=OFF -DBUILD_VISUALIZER=OFF \
  -DBUILD_STATIC_LIBRARIES=OFF -DBUILD_DYNAMIC_LIBRARIES=ON
cmake --build "$BUILD/obj" --parallel "$JOBS"
cmake --install "$BUILD/obj"
echo "Simbody $TAG (Release) installed in $PREFIX"
echo "configure mechgen with -DMECHGEN_SIMBODY_RELEASE_DIR=$PREFIX"
