#!/bin/bash
# `simpli train` stopped by a signal: the run finishes its step, writes a checkpoint and exits
# with 128 + signal (130 SIGINT, 143 SIGTERM); --resume continues from that checkpoint and the
# log keeps exactly one row per step; `simpli eval` reads the run's weights and config.
# Usage: train_signal.sh SIMPLI SCENE TRAIN_CONFIG WORKDIR INT|TERM
set -u
simpli=$1 scene=$2 config=$3 work=$4 sig=$5
fail() { echo "FAIL: $*"; for f in "$work"/out* "$work"/err*; do echo "--- $f"; cat "$f"; done; exit 1; }
rm -rf "$work" && mkdir -p "$work" || exit 1
run="$work/run"

"$simpli" train "$scene" --config "$config" --out "$run" --size 48x32 --steps 100000 \
  --checkpoint-every 100000 > "$work/out1" 2> "$work/err1" &
pid=$!
# Wait for the first logged step (header + one row), then signal.
for _ in $(seq 1 1200); do
  if [ -f "$run/log.csv" ] && [ "$(wc -l < "$run/log.csv")" -ge 2 ]; then break; fi
  kill -0 "$pid" 2> /dev/null || fail "train exited before its first step"
  sleep 0.25
done
[ "$(wc -l < "$run/log.csv")" -ge 2 ] || fail "no step logged in time"
kill -"$sig" "$pid"
wait "$pid"
rc=$?
if [ "$sig" = INT ]; then expect=130; else expect=143; fi
[ "$rc" -eq "$expect" ] || fail "exit code $rc, expected $expect"
grep -q "SIG$sig received; checkpoint written" "$work/err1" || fail "no stop message on stderr"
grep -q "^stopped at step" "$work/out1" || fail "no 'stopped at step' on stdout"
ckpt=$(ls -d "$run"/checkpoints/step_* 2> /dev/null | tail -n 1)
[ -n "$ckpt" ] || fail "no checkpoint"
for f in weights.safetensors optimizer.safetensors state.json; do
  [ -s "$ckpt/$f" ] || fail "checkpoint lacks $f"
done
[ -s "$run/weights.safetensors" ] || fail "no run weights"
[ -z "$(ls -A "$run/checkpoints" | grep '^\.')" ] || fail "temporary files left behind"
step=$((10#${ckpt##*step_}))
rows=$(($(wc -l < "$run/log.csv") - 1))
[ "$rows" -eq "$step" ] || fail "log has $rows rows, checkpoint is at step $step"

# Resume for one more step (the run's own config; no --config needed).
"$simpli" train "$scene" --out "$run" --resume --size 48x32 --steps $((step + 1)) \
  > "$work/out2" 2> "$work/err2" || fail "resume failed"
grep -q "resumed from .*step_0*$step at step $step" "$work/err2" || fail "no resume message"
grep -q "^finished at step $((step + 1))" "$work/out2" || fail "resume did not finish"
rows=$(($(wc -l < "$run/log.csv") - 1))
[ "$rows" -eq $((step + 1)) ] || fail "log has $rows rows after the resume, expected $((step + 1))"

# A new run into the same folder is refused.
"$simpli" train "$scene" --config "$config" --out "$run" > "$work/out3" 2> "$work/err3" \
  && fail "a second run into a used folder was accepted"
grep -q "already exists and is not empty; use --resume" "$work/err3" || fail "no clear error"

# eval reads the run's weights and config (with SIGTERM: the config from the weights' metadata).
config_arg=(--config "$run/config.json")
[ "$sig" = TERM ] && config_arg=()
"$simpli" eval "$scene" --weights "$run/weights.safetensors" "${config_arg[@]}" \
  --size 48x32 --views 2 --novel 1 --repeats 2 > "$work/out4" 2> "$work/err4" || fail "eval failed"
grep -Eq "model +PSNR +[0-9.]+ \+- [0-9.]+ dB +SSIM" "$work/out4" || fail "eval: no model line"
grep -Eq "nearest source view +PSNR" "$work/out4" || fail "eval: no baseline line"
cat "$work/out1" "$work/out2" "$work/out4"
echo "PASS"
