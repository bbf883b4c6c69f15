#!/usr/bin/env bash
# The MPI-only baseline of the shipped network at its recipe and budget (issue 10), in two phases
# that follow the shipped network's own history from its start (model/weights/wide-crop-5050):
#   phase 1  RUNS/mpi-prior: tiny-prior-mpi-world-wide-crop-margin, 1 150 steps (the prior run);
#   phase 2  RUNS/mpi-combo: tiny-prior-mpi-world-wide-crop-margin-sharp-v6 from phase 1's
#            averaged weights at its last step, 1 000 steps (the combo run's share of the shipped
#            network's budget).
#   bash scripts/mpi-baseline.sh RUNS
# Each call starts or resumes whichever phase is due (a finished phase 1 starts phase 2), through
# scripts/train-long.sh: niced, one thread (SIMPLI_RUN_THREADS=N: N), checkpoints every 50 steps,
# the flower monitor every 100 on ../shared/realdata/flower when it exists (SIMPLI_VALIDATE=SCENE:
# another scene, empty: none). PHASE1_STEPS / PHASE2_STEPS change the budgets.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
runs=${1:?usage: mpi-baseline.sh RUNS_DIR}
phase1_steps=${PHASE1_STEPS:-1150}
phase2_steps=${PHASE2_STEPS:-1000}
recipes=$root/model/configs/training
flower=$root/../shared/realdata/flower

export SIMPLI_RUN_THREADS=${SIMPLI_RUN_THREADS:-1} SIMPLI_CHECKPOINT_EVERY=50 SIMPLI_VALIDATE_EVERY=100
if [[ -z "${SIMPLI_VALIDATE+set}" && -d "$flower" ]]; then # SIMPLI_VALIDATE= : no monitor
  SIMPLI_VALIDATE=$(cd "$flower" && pwd)
  export SIMPLI_VALIDATE
fi

# The step of a run's newest checkpoint (0 when it has none).
last_step() {
  local dir step=0
  for dir in "$1"/out/checkpoints/step_*; do
    [[ -d "$dir" ]] && step=$((10#${dir##*/step_}))
  done
  echo "$step"
}

phase1=$runs/mpi-prior phase2=$runs/mpi-combo
for run in "$phase1" "$phase2"; do
  if [[ -f "$run/pid" ]] && kill -0 "$(cat "$run/pid")" 2> /dev/null; then
    echo "mpi-baseline.sh: $run is training (pid $(cat "$run/pid")); nothing started"
    exit 0
  fi
done
done1=$(last_step "$phase1")
if ((done1 < phase1_steps)); then
  SIMPLI_INIT_WEIGHTS=$root/model/weights/wide-crop-5050.safetensors \
    SIMPLI_TRAIN_ARGS="--steps $phase1_steps" \
    bash "$root/scripts/train-long.sh" "$phase1" "$recipes/tiny-prior-mpi-world-wide-crop-margin.json"
  exit 0
fi
if (($(last_step "$phase2") >= phase2_steps)); then
  echo "mpi-baseline.sh: both phases are done ($phase1 at $done1, $phase2 at $phase2_steps steps)"
  exit 0
fi
init=$(printf '%s/out/checkpoints/step_%08d/weights_ema.safetensors' "$phase1" "$done1")
[[ -f "$init" ]] || { echo "mpi-baseline.sh: $init: no averaged weights to start phase 2" >&2; exit 1; }
SIMPLI_INIT_WEIGHTS=$init SIMPLI_TRAIN_ARGS="--steps $phase2_steps" \
  bash "$root/scripts/train-long.sh" "$phase2" "$recipes/tiny-prior-mpi-world-wide-crop-margin-sharp-v6.json"
