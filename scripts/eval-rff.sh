#!/usr/bin/env bash
# The README's real-photo results: the paper's Real Forward-Facing protocol (simpli eval
# --protocol rff: 512x384, sources and novel views drawn without replacement from all frames,
# 8 novel views, 20 repeats, central 90% crop) at 2, 5 and 8 source views, for one or more
# networks scored on the same samples, with comparison pictures.
#   bash scripts/eval-rff.sh SCENE OUT [WEIGHTS[,WEIGHTS2,...] [EVAL OPTIONS...]]
# SCENE: an LLFF scene folder (e.g. ../shared/realdata/flower); OUT: a folder for the logs,
# views.csv and pictures (OUT/views_V/); WEIGHTS default to the shipped network and the
# plane-sweep stereo yardstick (baseline:plane-sweep, no network); further arguments go to every
# `simpli eval` (e.g. --input-scale 0.75, the shipped network's best input size on 512x384 photos).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if (($# < 2)); then
  echo "usage: bash scripts/eval-rff.sh SCENE OUT [WEIGHTS[,WEIGHTS2,...] [EVAL OPTIONS...]]" >&2
  exit 2
fi
scene=$1 out=$2
weights=${3:-$root/model/weights/default.safetensors,baseline:plane-sweep}
extra=("${@:4}")
simpli=${SIMPLI:-$root/build/bin/simpli}
mkdir -p "$out"
for views in 2 5 8; do
  echo "== $views source views"
  "$simpli" eval "$scene" --weights "$weights" --protocol rff --views "$views" --seed 1 \
    --out "$out/views_$views" "${extra[@]}" | tee "$out/views_$views.log"
done
