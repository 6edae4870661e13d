#!/usr/bin/env bash
# The README's first command: install what is missing, build, and run the main job
# (sweep a full crank turn of the shipped `fourbar` model, print a table, write CSV and SVG).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
mkdir -p out
./build/models/fourbar_sweep --steps 360 --csv out/fourbar.csv --svg out/fourbar.svg --table 8
