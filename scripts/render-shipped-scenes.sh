#!/usr/bin/env bash
# Renders every shipped scene (and the built-in default) with the patch method and heat maps into
# OUT/<scene>/, for byte-for-byte comparisons of images and counters across a change:
#   bash scripts/render-shipped-scenes.sh /tmp/before     # on the old commit
#   bash scripts/render-shipped-scenes.sh /tmp/after      # on the new one
#   diff -r /tmp/before /tmp/after && echo identical
# PATCHSIM (default build/pipeline/app/patchsim) names the binary; extra arguments go to render.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: render-shipped-scenes.sh OUT [render options...]}
shift
bin=${PATCHSIM:-build/pipeline/app/patchsim}
mkdir -p "$out"
for scene in scenes/*.json; do
  name=$(basename "$scene" .json)
  "$bin" render "$scene" -q --no-progress --heatmaps -o "$out/$name" "$@" > /dev/null
done
"$bin" render -q --no-progress --heatmaps -o "$out/builtin-default" "$@" > /dev/null
echo "rendered $(ls -d "$out"/*/ | wc -l) scenes into $out"
