#!/bin/bash
# `simpli train` stopped by signals always leaves a valid checkpoint (issue 9):
#   1. SIGTERM, then SIGTERM again every few milliseconds until it exits: every further signal is
#      absorbed until the checkpoint is written; exit 143.
#   2. Under `timeout -s TERM` (SIGTERM to the process, then to its whole process group) with
#      several durations, from start-up to mid-run, checkpointing every step: exit 143 every time,
#      a complete checkpoint, no temporaries.
#   3. SIGKILL just after a step was logged (while its checkpoint is written) and a little later:
#      every checkpoint folder there is complete (the writes are atomic); the run resumes from its
#      newest checkpoint.
# Usage: train_timeout.sh SIMPLI SCENE TRAIN_CONFIG WORKDIR
set -u
simpli=$1 scene=$2 config=$3 work=$4
fail() {
  echo "FAIL: $*"
  for f in "$work"/out* "$work"/err*; do [ -f "$f" ] && { echo "--- $f"; tail -n 20 "$f"; }; done
  exit 1
}
rm -rf "$work" && mkdir -p "$work" || exit 1
# (No shell function for a background train: `kill $!` would signal the subshell, not simpli.)
common=(--config "$config" --size 48x32 --steps 100000)

# Every checkpoint folder of a run holds its complete set of files; prints the newest step.
check_checkpoints() { # $1: run folder, $2: what happened
  local run=$1 ckpt newest=-1
  for ckpt in "$run"/checkpoints/step_*; do
    [ -d "$ckpt" ] || continue
    for f in weights.safetensors optimizer.safetensors state.json; do
      [ -s "$ckpt/$f" ] || fail "$2: $ckpt lacks $f"
    done
    python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); assert s["format"]=="simpli-train-checkpoint"' \
      "$ckpt/state.json" || fail "$2: $ckpt/state.json is not a complete checkpoint state"
    newest=$((10#${ckpt##*step_}))
  done
  echo "$newest"
}

# 1. A storm of SIGTERMs.
run="$work/storm"
"$simpli" train "$scene" "${common[@]}" --checkpoint-every 100000 --out "$run" \
  > "$work/out_storm" 2> "$work/err_storm" &
pid=$!
for _ in $(seq 1 1200); do
  [ -f "$run/log.csv" ] && [ "$(wc -l < "$run/log.csv")" -ge 2 ] && break
  kill -0 "$pid" 2> /dev/null || fail "train exited before its first step"
  sleep 0.25
done
sent=0
while kill -TERM "$pid" 2> /dev/null; do
  sent=$((sent + 1))
  sleep 0.005
done
wait "$pid"
rc=$?
# (Killed by SIGTERM and exit(143) look the same to the shell: the message tells them apart.)
[ "$rc" -eq 143 ] || fail "storm: exit $rc after $sent SIGTERMs, expected 143"
grep -q "SIGTERM received; checkpoint written" "$work/err_storm" \
  || fail "storm: killed by one of $sent SIGTERMs (no stop message)"
[ "$sent" -ge 2 ] || fail "storm: only $sent SIGTERM delivered"
step=$(check_checkpoints "$run" storm) || fail "$step"
[ "$step" -ge 1 ] || fail "storm: no checkpoint"
[ -z "$(ls -A "$run/checkpoints" | grep '^\.')" ] || fail "storm: temporaries left"
echo "storm: $sent SIGTERMs, checkpoint at step $step"

# 2. timeout -s TERM, several durations (the first lands in start-up).
for duration in 0.5 1 2 3 4 6; do
  run="$work/timeout_$duration"
  timeout --preserve-status -s TERM "$duration" "$simpli" train "$scene" "${common[@]}" \
    --checkpoint-every 1 --out "$run" \
    > "$work/out_t$duration" 2> "$work/err_t$duration"
  rc=$?
  [ "$rc" -eq 143 ] || fail "timeout $duration: exit $rc, expected 143"
  grep -q "SIGTERM received; checkpoint written" "$work/err_t$duration" \
    || fail "timeout $duration: killed (no stop message)"
  step=$(check_checkpoints "$run" "timeout $duration") || fail "$step"
  [ "$step" -ge 0 ] || fail "timeout $duration: no checkpoint"
  [ -s "$run/weights.safetensors" ] || fail "timeout $duration: no run weights"
  [ -z "$(ls -A "$run/checkpoints" | grep '^\.')" ] || fail "timeout $duration: temporaries left"
  rows=$(($(wc -l < "$run/log.csv") - 1))
  [ "$rows" -eq "$step" ] || fail "timeout $duration: log has $rows rows, checkpoint at $step"
  echo "timeout $duration s: exit 143, checkpoint at step $step"
done

# 3. SIGKILL just after a step was logged, when its checkpoint is being written (every step
#    checkpoints), and a little later: never a partial checkpoint; the run resumes from the newest.
run="$work/killed"
rows() { if [ -f "$run/log.csv" ]; then echo $(($(wc -l < "$run/log.csv") - 1)); else echo 0; fi; }
"$simpli" train "$scene" "${common[@]}" --checkpoint-every 1 --out "$run" > "$work/out_k0" \
  2> "$work/err_k0" &
pid=$!
for _ in $(seq 1 1200); do # a first checkpoint, so that there is always one to resume from
  [ -d "$run/checkpoints/step_00000001" ] && break
  kill -0 "$pid" 2> /dev/null || fail "train exited"
  sleep 0.05
done
for delay in 0 0.01 0.03 0.1 0.3; do
  before=$(rows)
  for _ in $(seq 1 6000); do
    [ "$(rows)" -gt "$before" ] && break
    kill -0 "$pid" 2> /dev/null || fail "train exited"
    sleep 0.01
  done
  sleep "$delay"
  kill -9 "$pid" 2> /dev/null
  wait "$pid" 2> /dev/null
  step=$(check_checkpoints "$run" "SIGKILL") || fail "$step"
  [ "$step" -ge 1 ] || fail "SIGKILL: no checkpoint"
  "$simpli" train "$scene" --out "$run" --resume --size 48x32 --steps 100000 --checkpoint-every 1 \
    > "$work/out_k" 2> "$work/err_k" &
  pid=$!
  for _ in $(seq 1 1200); do
    grep -q "resumed from .*step_0*$step at step $step" "$work/err_k" 2> /dev/null && break
    kill -0 "$pid" 2> /dev/null || fail "resume after SIGKILL exited"
    sleep 0.05
  done
  grep -q "resumed from .*step_0*$step at step $step" "$work/err_k" || fail "no resume from $step"
  echo "SIGKILL ${delay}s after step $((before + 1)) was logged: resumed from step $step"
done
kill -TERM "$pid"
wait "$pid"
rc=$?
[ "$rc" -eq 143 ] || fail "last resume: exit $rc after SIGTERM, expected 143"
grep -q "SIGTERM received; checkpoint written" "$work/err_k" || fail "last resume: killed"
out=$(check_checkpoints "$run" final) || fail "$out"
echo "PASS"
