#!/bin/bash
# scripts/train-long.sh, the long run's launcher: a bad SIMPLI_INIT_WEIGHTS is refused before the
# run folder exists; =none starts from a random initialisation, a file warm-starts from it, and
# launch.log says which; a second launch resumes from the checkpoint with the stored options;
# the weights of every SIMPLI_KEEP_WEIGHTS_EVERY-th step stay in RUN/out/kept.
# Usage: train_long.sh SIMPLI SOURCE_DIR TRAIN_CONFIG WORKDIR
set -u
simpli=$1 root=$2 config=$3 work=$4
script="$root/scripts/train-long.sh"
fail() { echo "FAIL: $*"; for f in "$work"/*/launch.log "$work"/*/train.log "$work"/err*; do
  [ -f "$f" ] && { echo "--- $f"; cat "$f"; }; done; exit 1; }
rm -rf "$work" && mkdir -p "$work" || exit 1
export SIMPLI="$simpli" SIMPLI_NICE=0 SIMPLI_CHECKPOINT_EVERY=1

# The background training is not this shell's child: poll its pid until it exits.
wait_run() {
  local pid
  pid=$(cat "$1/pid") || fail "$1: no pid file"
  for _ in $(seq 1 2400); do kill -0 "$pid" 2> /dev/null || return 0; sleep 0.25; done
  fail "$1: training still running after 10 minutes"
}
launch() { # RUN_DIR, then the environment decides
  bash "$script" "$1" "$config" > "$work/out" 2> "$work/err" || fail "launch of $1 failed"
  wait_run "$1"
}

SIMPLI_INIT_WEIGHTS="$work/missing.safetensors" bash "$script" "$work/bad" "$config" \
  2> "$work/err_bad" && fail "a missing SIMPLI_INIT_WEIGHTS was accepted"
grep -q "SIMPLI_INIT_WEIGHTS=$work/missing.safetensors: no such file" "$work/err_bad" ||
  fail "no named error for the missing init weights"
[ ! -e "$work/bad" ] || fail "a refused launch left a run folder behind"
bash "$script" "$work/bad" "$work/missing.json" 2> "$work/err_bad_config" &&
  fail "a missing config was accepted"
grep -q "missing.json: no such file" "$work/err_bad_config" || fail "no named error for the config"

SIMPLI_RUN_THREADS=two bash "$script" "$work/bad" "$config" 2> "$work/err_bad_threads" &&
  fail "a bad SIMPLI_RUN_THREADS was accepted"
grep -q "SIMPLI_RUN_THREADS=two: not a thread count" "$work/err_bad_threads" ||
  fail "no named error for the thread count"
[ ! -e "$work/bad" ] || fail "a refused launch left a run folder behind"

for bad in SIMPLI_CHECKPOINT_EVERY=0 SIMPLI_VALIDATE_EVERY=x SIMPLI_VALIDATE=$work/nowhere \
  SIMPLI_KEEP_WEIGHTS_EVERY=-1; do
  env "$bad" bash "$script" "$work/bad" "$config" 2> "$work/err_bad_env" && fail "$bad was accepted"
  grep -q "${bad%%=*}=${bad#*=}: " "$work/err_bad_env" || fail "no named error for $bad"
  [ ! -e "$work/bad" ] || fail "a refused launch ($bad) left a run folder behind"
done

scene="$root/datasets_small/synthetic/scene_00"
SIMPLI_RUN_THREADS=1 SIMPLI_INIT_WEIGHTS=none SIMPLI_TRAIN_ARGS="--size 48x32 --steps 2" \
  SIMPLI_VALIDATE="$scene" SIMPLI_VALIDATE_EVERY=7 SIMPLI_KEEP_WEIGHTS_EVERY=2 launch "$work/random"
grep -q -- "--validate $scene --validate-every 7" "$work/random/launch.log" ||
  fail "the first launch does not validate"
grep -q "threads: 1" "$work/random/launch.log" || fail "launch.log does not give the threads"
grep -q "random initialisation" "$work/random/launch.log" || fail "launch.log does not say random"
grep -q "finished at step 2 of 2" "$work/random/train.log" || fail "random run did not finish"
[ -s "$work/random/out/kept/step_00000002.safetensors" ] || fail "step 2's weights were not kept"
[ "$(ls "$work/random/out/kept")" = step_00000002.safetensors ] || fail "kept more than step 2"
# Resumed: the stored options (2 steps) hold, the new ones are ignored.
SIMPLI_TRAIN_ARGS="--size 64x48 --steps 3" launch "$work/random"
grep -q "resuming" "$work/random/launch.log" || fail "second launch did not resume"
[ "$(grep -c "threads: 1" "$work/random/launch.log")" -eq 2 ] || fail "resume lost the threads"
[ "$(grep -c -- "--validate $scene --validate-every 7" "$work/random/launch.log")" -eq 2 ] ||
  fail "resume lost the validation settings"
[ "$(grep -c -- "--checkpoint-every 1" "$work/random/launch.log")" -eq 2 ] ||
  fail "resume lost the checkpoint interval"
[ "$(grep -c -- "--keep-weights-every 2" "$work/random/launch.log")" -eq 2 ] ||
  fail "resume lost the interval of the kept weights"
[ "$(grep -c "finished at step 2 of 2" "$work/random/train.log")" -eq 2 ] ||
  fail "the resumed run did not keep its stored options"

# A binary older than --keep-weights-every (a resumed run keeps its own) is not given the flag.
old="$work/old-simpli"
printf '#!/bin/sh\n[ "$2" = --help ] && { echo "--checkpoint-every N"; exit 0; }\necho "$@" > "%s"\n' \
  "$work/old_args" > "$old" && chmod +x "$old" || fail "cannot write the stand-in binary"
SIMPLI="$old" SIMPLI_INIT_WEIGHTS=none launch "$work/old"
grep -q -- "--checkpoint-every 1" "$work/old_args" || fail "the stand-in binary did not run"
grep -q -- "--keep-weights-every" "$work/old_args" && fail "an older binary was given --keep-weights-every"

weights="$root/model/weights/default.safetensors"
sha=$(sha1sum < "$weights" | cut -c1-7)
SIMPLI_INIT_WEIGHTS="$weights" SIMPLI_TRAIN_ARGS="--size 48x32 --steps 1" launch "$work/warm"
grep -q "warm start from $weights (sha1 $sha)" "$work/warm/launch.log" ||
  fail "launch.log does not name the init weights"
grep -qi "init" "$work/warm/train.log" || fail "train.log does not mention the init weights"
cmp -s "$weights" "$work/warm/bin/init.safetensors" || fail "init weights not kept in the run"
grep -q -- "--keep-weights-every 100" "$work/warm/launch.log" || fail "no default keep interval"
[ ! -e "$work/warm/out/kept" ] || fail "a 1-step run kept weights of step 100"
echo "PASS: train-long.sh refusals, random start, resume, kept weights and warm start"
