#!/usr/bin/env bash
# Renders the mechanism pictures of the README (docs/pictures/<model>.png): each model's
# sweep command draws its SVG (still: the first configuration, faded snapshots, the traced
# paths), rsvg-convert (Debian: librsvg2-bin) turns it into a PNG.
#   tools/make_pictures.sh [build-dir [model...]]
# Default models: quick_return geared_fivebar cam_roller. Needs the models' <model>_sweep
# commands built (ninja -C build quick_return_sweep ...).
set -euo pipefail
build=${1:-build}
shift || true
models=("$@")
[ ${#models[@]} -gt 0 ] || models=(quick_return geared_fivebar cam_roller)
root=$(cd "$(dirname "$0")/.." && pwd)
out="$root/docs/pictures"
mkdir -p "$out"
command -v rsvg-convert > /dev/null || { echo "make_pictures.sh: rsvg-convert not found (apt-get install librsvg2-bin)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for m in "${models[@]}"; do
  "$build/models/${m}_sweep" --steps 360 --no-animation --svg "$tmp/$m.svg" --table 0 > /dev/null
  rsvg-convert --width 640 -o "$out/$m.png" "$tmp/$m.svg"
  echo "wrote $out/$m.png"
done
