#!/bin/bash
# scripts/mpi-baseline.sh, the two-phase launcher of the MPI-only baseline, with a stand-in for
# simpli (it records its arguments and exits): an empty runs folder starts phase 1 from the
# shipped network's start with its recipe and budget; a finished phase 1 starts phase 2 from its
# averaged weights; a phase 1 without them is a named error that starts nothing; a run in
# progress or two finished phases start nothing.
# Usage: mpi_baseline.sh SOURCE_DIR WORKDIR
set -u
root=$1 work=$2
script="$root/scripts/mpi-baseline.sh"
recipes="$root/model/configs/training"
fail() { echo "FAIL: $*"; for f in "$work"/runs/*/launch.log "$work"/err*; do
  [ -f "$f" ] && { echo "--- $f"; cat "$f"; }; done; exit 1; }
rm -rf "$work" && mkdir -p "$work/runs" || exit 1
printf '#!/bin/bash\necho "$@" >> %s/calls\n' "$work" > "$work/fake-simpli"
chmod +x "$work/fake-simpli"
export SIMPLI="$work/fake-simpli" SIMPLI_NICE=0 SIMPLI_VALIDATE=
runs="$work/runs"
# The stand-in runs in the background, not as this shell's child: poll the run's pid until it exits.
settle() {
  local pid
  pid=$(cat "$1/pid") || fail "$1: no pid file"
  for _ in $(seq 1 400); do kill -0 "$pid" 2> /dev/null || return 0; sleep 0.25; done
  fail "$1: the stand-in still runs after 100 s"
}

bash "$script" "$runs" > "$work/out1" 2> "$work/err1" || fail "phase 1 launch failed"
settle "$runs/mpi-prior"
cmp -s "$recipes/tiny-prior-mpi-world-wide-crop-margin.json" "$runs/mpi-prior/bin/config.json" ||
  fail "phase 1 does not train the margin recipe"
cmp -s "$root/model/weights/wide-crop-5050.safetensors" "$runs/mpi-prior/bin/init.safetensors" ||
  fail "phase 1 does not start from wide-crop-5050"
grep -q -- "--steps 1150" "$work/calls" || fail "phase 1 is not 1150 steps"
grep -q "threads: 1" "$runs/mpi-prior/launch.log" || fail "phase 1 does not run on one thread"

# Phase 1 still without its last checkpoint: launching again resumes it.
mkdir -p "$runs/mpi-prior/out/checkpoints/step_00000600"
bash "$script" "$runs" > "$work/out2" 2> "$work/err2" || fail "phase 1 resume failed"
settle "$runs/mpi-prior"
grep -q "resuming" "$runs/mpi-prior/launch.log" || fail "phase 1 was not resumed"
[ ! -e "$runs/mpi-combo" ] || fail "phase 2 started before phase 1 finished"

# Phase 1 finished without averaged weights: a named error, nothing started.
mkdir -p "$runs/mpi-prior/out/checkpoints/step_00001150"
bash "$script" "$runs" > "$work/out3" 2> "$work/err3" && fail "phase 2 started without weights"
grep -q "step_00001150/weights_ema.safetensors: no averaged weights" "$work/err3" ||
  fail "no named error for the missing averaged weights"
[ ! -e "$runs/mpi-combo" ] || fail "a refused phase 2 left a run folder behind"

# With them, phase 2 starts from them with the sharp-v6 recipe and 1000 steps.
echo "ema" > "$runs/mpi-prior/out/checkpoints/step_00001150/weights_ema.safetensors"
bash "$script" "$runs" > "$work/out4" 2> "$work/err4" || fail "phase 2 launch failed"
settle "$runs/mpi-combo"
cmp -s "$recipes/tiny-prior-mpi-world-wide-crop-margin-sharp-v6.json" \
  "$runs/mpi-combo/bin/config.json" || fail "phase 2 does not train the sharp-v6 recipe"
cmp -s "$runs/mpi-prior/out/checkpoints/step_00001150/weights_ema.safetensors" \
  "$runs/mpi-combo/bin/init.safetensors" || fail "phase 2 does not start from phase 1's average"
grep -q -- "--steps 1000" "$work/calls" || fail "phase 2 is not 1000 steps"

# A run in progress: nothing started.
sleep 30 &
echo $! > "$runs/mpi-combo/pid"
calls=$(wc -l < "$work/calls")
bash "$script" "$runs" > "$work/out5" 2> "$work/err5" || fail "a running phase made an error"
grep -q "is training" "$work/out5" || fail "a running phase is not reported"
[ "$(wc -l < "$work/calls")" -eq "$calls" ] || fail "a second process was started"
kill %1 2> /dev/null
wait 2> /dev/null

# Both phases done: nothing started.
mkdir -p "$runs/mpi-combo/out/checkpoints/step_00001000"
bash "$script" "$runs" > "$work/out6" 2> "$work/err6" || fail "finished phases made an error"
grep -q "both phases are done" "$work/out6" || fail "finished phases are not reported"
[ "$(wc -l < "$work/calls")" -eq "$calls" ] || fail "a finished baseline was relaunched"
echo "PASS: mpi-baseline.sh phases, budgets, starts and refusals"
