#!/usr/bin/env bash
# Configures and builds mechgen in ./build (Release, Ninja). Used by the two commands.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --parallel 2
