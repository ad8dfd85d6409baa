#!/usr/bin/env bash
# Renders every shipped scene (and the built-in default) into OUT/<scene>/, for byte-for-byte
# comparisons of images and counters across a change:
#   bash scripts/render-shipped-scenes.sh /tmp/before     # on the old commit
#   bash scripts/render-shipped-scenes.sh /tmp/after      # on the new one
#   diff -r /tmp/before /tmp/after && echo identical
# By default with the patch method and heat maps. METHODS=all renders every visibility method
# (each into OUT/<scene>/<method>/, heat maps where the method counts per pixel) at a small film
# (--width 96 --height 72 --spp 4), then adds a sweep's CSV, verify-tiles' summary and an explore
# CSV. PATCHSIM (default build/pipeline/app/patchsim) names the binary; extra arguments go to
# render.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: render-shipped-scenes.sh OUT [render options...]}
shift
bin=${PATCHSIM:-build/pipeline/app/patchsim}
mkdir -p "$out"
if [ "${METHODS:-}" != "all" ]; then
  for scene in scenes/*.json; do
    name=$(basename "$scene" .json)
    "$bin" render "$scene" -q --no-progress --heatmaps -o "$out/$name" "$@" > /dev/null
  done
  "$bin" render -q --no-progress --heatmaps -o "$out/builtin-default" "$@" > /dev/null
  echo "rendered $(ls -d "$out"/*/ | wc -l) scenes into $out"
  exit 0
fi
methods="patch reference triangle-bbox interval interleaved postprocess hybrid reprojection tfragment"
small=(--width 96 --height 72 --spp 4)
for scene in scenes/*.json; do
  name=$(basename "$scene" .json)
  for method in $methods; do
    heat=()
    case $method in patch|postprocess|hybrid|reprojection) heat=(--heatmaps) ;; esac
    "$bin" render "$scene" -q --no-progress "${small[@]}" --method "$method" "${heat[@]}" \
      -o "$out/$name/$method" "$@" > /dev/null
  done
done
# The wall-time column of the sweep is dropped: it is the one figure that is not deterministic.
"$bin" sweep scenes/motion.json scenes/transparency.json --methods "${methods// /,}" --spp 1,2 \
  --repeats 1 --no-progress --converged-spp 8 -o "$out/.sweep" > /dev/null
cut -d, -f1-3,5- "$out/.sweep/results.csv" > "$out/sweep.csv"
rm -rf "$out/.sweep"
"$bin" verify-tiles --cases 300 --summary "$out/verify-tiles.csv" > /dev/null
"$bin" explore scenes/motion.json --grid docs/explore/tile_leaf_grid.json -o "$out/explore.csv" \
  > /dev/null 2>&1
echo "rendered every method on $(ls -d "$out"/*/ | wc -l) scenes, with sweep, verify-tiles and" \
  "explore outputs, into $out"
