#!/usr/bin/env bash
# The long training run of issue 10, resumable across sessions and machines:
#   bash scripts/train-long.sh RUN_DIR [CONFIG]
# CONFIG defaults to the shipped network's own recipe (`config=` below, the one place that names it):
# a run warm-starts from the shipped weights, so its network must be theirs.
# SIMPLI_VALIDATE=SCENE scores the network on that scene at checkpoints (RUN_DIR/out/val.csv,
# validation/, progress.png; every SIMPLI_VALIDATE_EVERY steps, default 100) and keeps the
# weights of the best score in RUN_DIR/out/best.safetensors (score them with `simpli eval`);
# SIMPLI_UPDATE_BINARY=1 replaces the run's copy of the binary with the tree's (SIMPLI=PATH: another
# binary than build/bin/simpli).
# SIMPLI_TRAIN_ARGS="--size 128x96 ..." adds options to `simpli train`; they are kept in
# RUN_DIR/bin/args on the first launch and reused when the run resumes. SIMPLI_VALIDATE,
# SIMPLI_VALIDATE_EVERY, SIMPLI_CHECKPOINT_EVERY (default 20) and SIMPLI_RUN_THREADS are kept in
# RUN_DIR/bin as well, each when given, so resuming is `bash scripts/train-long.sh RUN_DIR`;
# launch.log records every launch's command line.
# The averaged weights of every SIMPLI_KEEP_WEIGHTS_EVERY-th step (default 100, 0: none; kept in
# RUN_DIR/bin like those) stay in RUN_DIR/out/kept/ for equal-step comparisons.
# If RUN_DIR holds a checkpoint the run resumes from it; otherwise it warm-starts from the
# shipped weights (model/weights/default.safetensors) and says so in RUN_DIR/launch.log;
# SIMPLI_INIT_WEIGHTS=FILE starts from FILE instead, =none from a random initialisation (a
# network of another config than the shipped one, e.g. official-4l).
# The binary is copied into RUN_DIR/bin first, so rebuilding the tree never changes the program
# of a running run. Runs niced (SIMPLI_NICE, default 15) in the background; `kill -INT` checkpoints and stops it.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
run=${1:?usage: train-long.sh RUN_DIR [CONFIG]}
config=${2:-$root/model/configs/training/tiny-prior-world-wide-crop-margin-sharp-v6-ssim30-bushes12-big.json}
init=${SIMPLI_INIT_WEIGHTS:-$root/model/weights/default.safetensors}
# Checked before anything is written, so a mistyped path leaves no half-made run folder behind.
simpli=${SIMPLI:-$root/build/bin/simpli}
for file in "$config" "$simpli"; do
  [[ -f "$file" ]] || { echo "train-long.sh: $file: no such file" >&2; exit 1; }
done
for name in SIMPLI_CHECKPOINT_EVERY SIMPLI_VALIDATE_EVERY; do
  if [[ -n "${!name:-}" && ! "${!name}" =~ ^[1-9][0-9]*$ ]]; then
    echo "train-long.sh: $name=${!name}: not a positive step count" >&2
    exit 1
  fi
done
if [[ -n "${SIMPLI_KEEP_WEIGHTS_EVERY:-}" && ! "$SIMPLI_KEEP_WEIGHTS_EVERY" =~ ^[0-9]+$ ]]; then
  echo "train-long.sh: SIMPLI_KEEP_WEIGHTS_EVERY=$SIMPLI_KEEP_WEIGHTS_EVERY: not a step count (0: keep none)" >&2
  exit 1
fi
if [[ -n "${SIMPLI_VALIDATE:-}" && ! -d "$SIMPLI_VALIDATE" ]]; then
  echo "train-long.sh: SIMPLI_VALIDATE=$SIMPLI_VALIDATE: no such scene folder" >&2
  exit 1
fi
if [[ -n "${SIMPLI_RUN_THREADS:-}" && ! "$SIMPLI_RUN_THREADS" =~ ^[0-9]+$ ]]; then
  echo "train-long.sh: SIMPLI_RUN_THREADS=$SIMPLI_RUN_THREADS: not a thread count" >&2
  exit 1
fi
if [[ "$init" != none && ! -f "$init" ]]; then
  echo "train-long.sh: SIMPLI_INIT_WEIGHTS=$init: no such file (a weights file or 'none')" >&2
  exit 1
fi
mkdir -p "$run/bin"
run=$(cd "$run" && pwd)
if [[ ! -x "$run/bin/simpli" || "${SIMPLI_UPDATE_BINARY:-0}" == 1 ]]; then
  cp "$simpli" "$run/bin/simpli.new" && mv "$run/bin/simpli.new" "$run/bin/simpli"
fi
if [[ ! -f "$run/bin/config.json" ]]; then
  if [[ "$init" == none ]]; then
    echo "none" > "$run/bin/init"
  else
    cp "$init" "$run/bin/init.safetensors"
    echo "$init (sha1 $(sha1sum < "$init" | cut -c1-7))" > "$run/bin/init"
  fi
  cp "$config" "$run/bin/config.json"
fi
# The config names its network relative to itself: keep the network configs beside it.
mkdir -p "$run/model/configs/training"
cp -n "$root"/model/configs/*.json "$run/model/configs/" 2>/dev/null || true
cp -n "$run/bin/config.json" "$run/model/configs/training/run.json"
# Settings given by the environment are kept in RUN_DIR/bin and reused when a later launch does
# not give them, so a resume is `bash scripts/train-long.sh RUN_DIR` alone.
remember() { # NAME VALUE DEFAULT: VALUE if given (and stored), else the stored value, else DEFAULT
  if [[ -n "$2" ]]; then
    printf '%s\n' "$2" > "$run/bin/$1"
    echo "$2"
  elif [[ -f "$run/bin/$1" ]]; then
    cat "$run/bin/$1"
  else
    echo "$3"
  fi
}
every=$(remember checkpoint_every "${SIMPLI_CHECKPOINT_EVERY:-}" 20)
validate=$(remember validate "${SIMPLI_VALIDATE:-}" "")
validate_every=$(remember validate_every "${SIMPLI_VALIDATE_EVERY:-}" 100)
keep_every=$(remember keep_weights_every "${SIMPLI_KEEP_WEIGHTS_EVERY:-}" 100)
if [[ ! -f "$run/bin/args" ]]; then
  printf '%s\n' "${SIMPLI_TRAIN_ARGS:-}" > "$run/bin/args"
fi
read -r -a extra_args < "$run/bin/args" || true
# SIMPLI_RUN_THREADS=N: the run's threads (PoCL, OpenBLAS, OpenCV), kept in RUN_DIR/bin/threads
# on the first launch that gives it (0 or unset: the libraries' defaults, all cores). Two runs
# on 2 cores go faster with 1 thread each than sharing both: a step takes 1.55x as long on 1
# thread as on 2 (tiny, wide-crop recipe), against 2x for time-sharing (docs/training.md).
if [[ -n "${SIMPLI_RUN_THREADS:-}" ]]; then
  echo "$SIMPLI_RUN_THREADS" > "$run/bin/threads"
fi
threads=$(cat "$run/bin/threads" 2> /dev/null || echo 0)
if [[ "$threads" != 0 ]]; then
  export POCL_MAX_PTHREAD_COUNT=$threads OPENBLAS_NUM_THREADS=$threads OPENCV_FOR_THREADS_NUM=$threads
fi
if [[ -n "$(ls -A "$run/out/checkpoints" 2>/dev/null)" ]]; then
  echo "$(date -Is) resuming $run/out" >> "$run/launch.log"
  args=(--out "$run/out" --resume --checkpoint-every "$every")
else
  rm -rf "$run/out"
  args=(--config "$run/model/configs/training/run.json" --out "$run/out" --checkpoint-every "$every")
  if [[ -f "$run/bin/init.safetensors" ]]; then
    echo "$(date -Is) no checkpoint in $run/out: warm start from $(cat "$run/bin/init" 2>/dev/null || echo "$run/bin/init.safetensors")" \
      "(tree at $(git -C "$root" rev-parse --short HEAD 2> /dev/null || echo unknown))" >> "$run/launch.log"
    args+=(--init-weights "$run/bin/init.safetensors")
  else
    echo "$(date -Is) no checkpoint in $run/out: random initialisation" \
      "(tree at $(git -C "$root" rev-parse --short HEAD 2> /dev/null || echo unknown))" >> "$run/launch.log"
  fi
fi
if [[ -n "$validate" ]]; then
  args+=(--validate "$validate" --validate-every "$validate_every")
fi
# A run's binary older than --keep-weights-every (a resumed run keeps its own binary) keeps none.
# (The help is read whole first: `| grep -q` could end the pipe early and fail it on SIGPIPE.)
help=$("$run/bin/simpli" train --help 2>&1 || true)
if [[ "$keep_every" != 0 && "$help" == *--keep-weights-every* ]]; then
  args+=(--keep-weights-every "$keep_every")
fi
args+=("${extra_args[@]}")
cd "$run"
echo "$(date -Is) threads: ${threads/#0/all cores}; simpli train synthetic:1 ${args[*]}" >> "$run/launch.log"
nohup nice -n "${SIMPLI_NICE:-15}" "$run/bin/simpli" train synthetic:1 "${args[@]}" >> "$run/train.log" 2>&1 &
echo "$!" > "$run/pid"
echo "training in the background: pid $(cat "$run/pid"), log $run/train.log"
