#!/usr/bin/env bash
# Throughput of simpli on 1 and 2 MPI ranks (docs/parallel.md), printed as a table:
#   training   samples/s of `simpli train` (tiny config) as 1 rank x 1 sample, 1 rank x 2 samples
#              per step (the same work as 2 ranks, in turn) and 2 ranks x 1 sample, with the
#              all-reduce's share of a step (it includes waiting for the slower rank)
#   inference  scenes/min of `simpli infer SCENES_DIR` over the bundled scenes on 1 and 2 ranks
# Each figure leaves out the first step / counts the network load separately (PoCL compiles
# kernels on first use). Usage: scripts/bench-mpi.sh [BUILD_DIR] [STEPS] [SIZE]
# (defaults build, 8, 96x64). Needs a build with SIMPLI_USE_MPI and mpiexec. Times depend on
# what else runs on the machine: run it on an idle one, or read the ratios.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$root/build}
steps=${2:-8}
size=${3:-96x64}
simpli="$build/bin/simpli"
work=$(mktemp -d /tmp/simpli-bench-mpi.XXXXXX)
trap 'rm -rf "$work"' EXIT
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
mpi2=(mpiexec --oversubscribe -n 2)
scene="$root/datasets_small/synthetic/scene_00"
config="$root/model/configs/training/tiny.json"

train() { # NAME LAUNCHER... -- ARGS...: prints the run's throughput line
  local name=$1; shift
  local launcher=()
  while [ "$1" != -- ]; do launcher+=("$1"); shift; done
  shift
  "${launcher[@]}" "$simpli" train "$scene" --config "$config" --size "$size" --steps "$steps" \
    --checkpoint-every 100000 --out "$work/$name" "$@" > "$work/$name.out" 2> "$work/$name.err"
  grep "^throughput" "$work/$name.out"
}
field() { sed -E "s#$1#\\1#" <<< "$2"; } # PATTERN with one group -> the group

echo "simpli bench-mpi: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); tiny config at $size, $steps steps"
t1=$(train one --  --samples-per-rank 1)
t1x2=$(train one_x2 -- --samples-per-rank 2)
t2=$(train two "${mpi2[@]}" --)
row() { # LABEL LINE: samples/s, ms per step, all-reduce and whole exchange shares
  local allreduce=- exchange=-
  if grep -q "all-reduce" <<< "$2"; then
    allreduce=$(field '.*\(([0-9.]+)% of a step\).*' "$2")
    exchange=$(field '.*exchange [0-9.]+ ms \(([0-9.]+)%\).*' "$2")
  fi
  printf "%-30s %10s %10s %13s %11s\n" "$1" "$(field 'throughput ([0-9.]+) samples.*' "$2")" \
    "$(field '.*, ([0-9]+) ms per step.*' "$2")" "$allreduce" "$exchange"
}
printf "\n%-30s %10s %10s %13s %11s\n" "training" "samples/s" "ms/step" "all-reduce %" "exchange %"
row "1 rank x 1 sample per step" "$t1"
row "1 rank x 2 samples per step" "$t1x2"
row "2 ranks x 1 sample per step" "$t2"

mkdir -p "$work/scenes"
for s in "$root"/datasets_small/synthetic/scene_*; do ln -s "$s" "$work/scenes/$(basename "$s")"; done
infer() { # NAME LAUNCHER...: prints the summary line
  local name=$1; shift
  "$@" "$simpli" infer "$work/scenes" --config tiny --init-random 1 --views 0,4,8 \
    --out "$work/$name" > "$work/$name.out" 2> "$work/$name.err"
  grep "scenes/min" "$work/$name.out"
}
i1=$(infer infer1)
i2=$(infer infer2 "${mpi2[@]}")
printf "\n%-30s %10s %10s %13s\n" "inference ($(ls "$work/scenes" | wc -l) scenes, tiny)" "scenes/min" "wall s" "ranks busy %"
for row in "1 rank|$i1" "2 ranks|$i2"; do
  line=${row#*|}
  printf "%-30s %10s %10s %13s\n" "${row%%|*}" "$(field '.* ([0-9.]+) scenes/min.*' "$line")" \
    "$(field '.*cancelled; ([0-9.]+) s .*' "$line")" "$(field '.*busy ([0-9]+)% .*' "$line")"
done
