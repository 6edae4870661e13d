#!/usr/bin/env bash
# Compares the generated kinematics of this tree with those of an earlier revision, in ulps,
# both against the long double evaluation of this tree's formulas (the figures a change of
# the generated arithmetic must state; tools/compare_generated_ulps.cc).
# Usage: tools/compare_generated_ulps.sh <revision> [model ...]
#   default models: those with SolveTrig and EvalKinematics among the RRR-dyad models.
set -euo pipefail
cd "$(dirname "$0")/.."
REV=${1:?usage: tools/compare_generated_ulps.sh <revision> [model ...]}
shift
MODELS=${*:-fourbar fourbar_crossed fourbar_loaded fourbar_massive fourbar_balanced watt_sixbar stephenson_sixbar fivebar fivebar_robot}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
DEFS=()
: > "$TMP/models.h"
LIST=""
for m in $MODELS; do
  U=$(echo "$m" | tr a-z A-Z)
  git show "$REV:generated/$m.h" |
    sed "s/namespace mech::$m\b/namespace mech::${m}_old/g; s/mech::$m::/mech::${m}_old::/g; s/MECH_${U}_INSTANTIATING/MECH_${U}_OLD_INSTANTIATING/g" > "$TMP/old_$m.h"
  # Header-only here: the templates instantiate in this program.
  DEFS+=(-DMECH_${U}_INSTANTIATING -DMECH_${U}_OLD_INSTANTIATING)
  echo "#include \"$PWD/generated/$m.h\"" >> "$TMP/models.h"
  echo "#include \"$TMP/old_$m.h\"" >> "$TMP/models.h"
  LIST="$LIST C($m)"
done
g++ -O2 -std=c++17 -I/usr/include/eigen3 -Iruntime/include "${DEFS[@]}" -DMODELS_INCLUDE="\"$TMP/models.h\"" -DMODELS_LIST="$LIST" \
  tools/compare_generated_ulps.cc -o "$TMP/compare"
echo "this tree against $REV ($(git rev-parse --short "$REV"))"
"$TMP/compare"
