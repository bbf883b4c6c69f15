#!/usr/bin/env bash
# A held-out synthetic test set of wide handheld rigs, for telling "the network has not learnt
# wide-baseline geometry" apart from "real photos look unlike the training data":
#   bash scripts/make-wide-set.sh OUT_DIR [SIZE]          (default size 128x96)
#   simpli eval OUT_DIR --weights A,B --views 4 --novel 2 --repeats 2 --seed 1
# World-style scenes (photo textures) of seeds 100-135 (SEED_FIRST, SEED_LAST) whose drawn camera spread (scene.json
# world.translation: farthest centre from the mean / nearest depth) is >= 0.15; flower's is 0.28.
# Training draws random 31-bit scene seeds, so these scenes are almost surely never trained on.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${1:?usage: make-wide-set.sh OUT_DIR [SIZE]}
size=${2:-128x96}
simpli=${SIMPLI:-$root/build/bin/simpli}
mkdir -p "$out"
for seed in $(seq ${SEED_FIRST:-100} ${SEED_LAST:-135}); do
  tmp="$out/.tmp-$seed"
  "$simpli" make-scene --out "$tmp" --seed "$seed" --style world --textures photo \
    --size "$size" --antialias 2 --force > /dev/null
  spread=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["world"]["translation"])' "$tmp/scene.json")
  if awk -v t="$spread" 'BEGIN { exit !(t >= 0.15) }'; then
    rm -rf "$out/seed_$seed"
    mv "$tmp" "$out/seed_$seed"
    echo "seed $seed: camera spread $spread"
  else
    rm -rf "$tmp"
  fi
done
