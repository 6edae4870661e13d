#!/usr/bin/env bash
# The README's first command: install what is missing, build the generator and the
# `fourbar` solver, and run the main job — sweep a full crank turn of models/fourbar.yaml,
# print a short table, write out/fourbar.csv and out/fourbar.svg.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh fourbar_sweep
mkdir -p out
./build/models/fourbar_sweep --steps 360 --csv out/fourbar.csv --svg out/fourbar.svg --table 8
