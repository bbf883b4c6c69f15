#!/usr/bin/env bash
# The main job (README): install missing packages, build, then build an MLI of a bundled
# scene with the shipped network, render it along a spiral, and score the network on the
# bundled scenes against the nearest-source-view baseline.
# Output: out/demo (or $SIMPLI_DEMO_OUT): mli/ (the MLI in the reference JPEG form, lossless/
# beside it, render_KKK.png of held-out views), spiral/ (rgb_NNN.png, depth_NNN.png).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SIMPLI_BUILD_DIR:-$root/build}
out=${SIMPLI_DEMO_OUT:-$root/out/demo}
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/build.sh"
simpli="$build/bin/simpli"
weights="$root/model/weights/default.safetensors"
scene="$root/datasets_small/synthetic/scene_00"
echo "== simpli devices"
"$simpli" devices
echo "== simpli infer: 6 source views of $scene -> $out/mli (held-out views 1, 5, 9 rendered and scored)"
"$simpli" infer "$scene" --weights "$weights" --views 0,2,4,6,8,10 --layers auto \
  --render-views 1,5,9 --out "$out/mli"
echo "== simpli render: a 24-frame spiral around the reference camera -> $out/spiral"
"$simpli" render "$out/mli" --trajectory spiral --frames 24 --out "$out/spiral"
echo "== simpli eval: held-out views of the bundled scenes (paper protocol) vs nearest source view"
"$simpli" eval "$root/datasets_small/synthetic" --weights "$weights" --views 4 --novel 2 \
  --repeats 2 --seed 1
