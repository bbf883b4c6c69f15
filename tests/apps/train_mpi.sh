#!/bin/bash
# `mpiexec -n 2 simpli train` (data-parallel, training/trainer.h), one case per ctest test:
#   equivalence  2 ranks x 1 sample == 1 rank x 2 samples (--samples-per-rank 2), exactly, on a
#                deterministic device (PoCL on one thread); a plain 1-sample run differs
#   tolerance    the same within float tolerance with PoCL's threads (atomic adds in any order)
#   resume       2 ranks stopped after 2 steps and resumed == 3 uninterrupted steps, exactly;
#                resumed by 1 rank or 2 x 2 samples: the message says how the streams change
#   signal_rank  SIGTERM to rank 1 alone: all ranks stop after the step, one checkpoint, 143
#   rank_exits   rank 1 exits after its first step without MPI_Finalize: the job ends (no
#                hang), non-zero, and mpiexec's message names rank 1 and its exit code
#   rank_killed  rank 1 killed (SIGKILL): the same, the message names rank 1 and the signal
#   rank_error   a named error on rank 0 (used run folder) ends both ranks with that message
# Usage: train_mpi.sh SIMPLI COMPARE_WEIGHTS MPIEXEC SCENE TRAIN_CONFIG WORKDIR CASE
set -u
simpli=$1 compare=$2 mpiexec=$3 scene=$4 config=$5 work=$6 case=$7
fail() { echo "FAIL: $*"; for f in "$work"/*.out "$work"/*.err; do [ -f "$f" ] && { echo "--- $f"; cat "$f"; }; done; exit 1; }
rm -rf "$work" && mkdir -p "$work" || exit 1
# Tests run as root in CI containers; Open MPI refuses that unless told.
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
mpi2=("$mpiexec" --oversubscribe -n 2)
small=(--config "$config" --size 64x48)

train() { # NAME [mpi] ARGS...: runs simpli train into $work/NAME, output in NAME.out / .err
  local name=$1; shift
  local launcher=()
  if [ "${1:-}" = mpi ]; then launcher=("${mpi2[@]}"); shift; fi
  timeout 600 "${launcher[@]}" "$simpli" train "$scene" "${small[@]}" --out "$work/$name" "$@" \
    > "$work/$name.out" 2> "$work/$name.err"
}
same() { "$compare" "$work/$1/weights.safetensors" "$work/$2/weights.safetensors" "$3" \
  || fail "$1 and $2: weights differ (above)"; }
differ() { "$compare" "$work/$1/weights.safetensors" "$work/$2/weights.safetensors" "$3" differ \
  || fail "$1 and $2: weights agree although the runs differ"; }
losses() { cut -d, -f1-11 "$work/$1/log.csv"; } # the log without step_ms

# The pid of rank $2 of a job started in the background as $1 (timeout -> mpiexec -> ranks).
rank_pid() {
  local p
  for p in $(pgrep -P "$1"); do
    tr '\0' '\n' < "/proc/$p/environ" 2> /dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$2" && { echo "$p"; return; }
    rank_pid "$p" "$2"
  done
}
wait_for_step() { # RUN PID: until RUN/log.csv has a row
  for _ in $(seq 1 1200); do
    [ -f "$1/log.csv" ] && [ "$(wc -l < "$1/log.csv")" -ge 2 ] && return
    kill -0 "$2" 2> /dev/null || fail "the job ended before its first step"
    sleep 0.25
  done
  fail "no step logged in time"
}

case $case in
equivalence)
  export POCL_MAX_PTHREAD_COUNT=1
  train one --steps 3 --samples-per-rank 2 || fail "one rank x 2 samples failed"
  train two mpi --steps 3 || fail "2 ranks failed"
  train plain --steps 3 || fail "the plain run failed"
  grep -q "data-parallel: 2 rank(s) x 1 sample(s) per step (MPI, rank 0 of 2" "$work/two.err" \
    || fail "no data-parallel line"
  grep -q "all-reduce .* ms per step" "$work/two.out" || fail "no all-reduce figure"
  same one two 0
  [ "$(losses one)" = "$(losses two)" ] || fail "the logs' losses differ"
  differ plain two 1e-6
  ;;
tolerance)
  train one --steps 3 --samples-per-rank 2 || fail "one rank x 2 samples failed"
  train two mpi --steps 3 || fail "2 ranks failed"
  same one two 1e-5
  ;;
resume)
  export POCL_MAX_PTHREAD_COUNT=1
  train full mpi --steps 3 || fail "the uninterrupted run failed"
  train part mpi --steps 2 --checkpoint-every 1 || fail "the first part failed"
  train part mpi --resume --steps 3 || fail "the resume failed"
  grep -q "resumed from .*step_00000002 at step 2" "$work/part.err" || fail "no resume message"
  same full part 0
  [ "$(losses full)" = "$(losses part)" ] || fail "the resumed log differs"
  grep -q '"sample_streams"' "$work/part/checkpoints/step_00000003/state.json" \
    || fail "the checkpoint lacks the streams"
  train part --resume --steps 4 || fail "resume by one rank failed"
  grep -q "the checkpoint has 2 sample stream(s), this run has 1 (1 rank(s) x 1 sample(s) per rank): streams 0..0 continue, streams 1..1 are dropped" \
    "$work/part.err" || fail "no message for fewer streams"
  train part mpi --resume --steps 5 --samples-per-rank 2 || fail "resume by 2 x 2 failed"
  grep -q "the checkpoint has 1 sample stream(s), this run has 4 .*streams 1..3 start fresh" \
    "$work/part.err" || fail "no message for more streams"
  [ "$(($(wc -l < "$work/part/log.csv") - 1))" -eq 5 ] || fail "the log does not have 5 rows"
  ;;
signal_rank)
  run="$work/run"
  timeout 900 "${mpi2[@]}" "$simpli" train "$scene" "${small[@]}" --out "$run" --steps 100000 \
    --checkpoint-every 100000 > "$work/run.out" 2> "$work/run.err" &
  job=$!
  wait_for_step "$run" "$job"
  pid=$(rank_pid "$job" 1)
  [ -n "$pid" ] || fail "rank 1 not found"
  kill -TERM "$pid"
  wait "$job"
  rc=$?
  [ "$rc" -eq 143 ] || fail "exit code $rc, expected 143"
  grep -q "^stopped at step" "$work/run.out" || fail "no 'stopped at step'"
  grep -q "SIGTERM received on 1 of 2 ranks; checkpoint written" "$work/run.err" \
    || fail "no stop message"
  ckpt=$(ls -d "$run"/checkpoints/step_* 2> /dev/null | tail -n 1)
  [ -n "$ckpt" ] || fail "no checkpoint"
  step=$((10#${ckpt##*step_}))
  [ "$(($(wc -l < "$run/log.csv") - 1))" -eq "$step" ] || fail "log rows != checkpoint step $step"
  ;;
rank_exits)
  start=$(date +%s)
  train run mpi --steps 50 --test-exit-rank 1 && fail "the job succeeded although rank 1 died"
  grep -q "Process name: \[\[[0-9]*,[0-9]*\],1\]" "$work/run.err" || fail "rank 1 not named"
  grep -q "Exit code: *3" "$work/run.err" || fail "exit code not named"
  [ ! -d "$work/run/checkpoints/step_00000050" ] || fail "the run went on"
  echo "ended $(($(date +%s) - start)) s after the start"
  ;;
rank_killed)
  run="$work/run"
  timeout 900 "${mpi2[@]}" "$simpli" train "$scene" "${small[@]}" --out "$run" --steps 100000 \
    --checkpoint-every 100000 > "$work/run.out" 2> "$work/run.err" &
  job=$!
  wait_for_step "$run" "$job"
  pid=$(rank_pid "$job" 1)
  [ -n "$pid" ] || fail "rank 1 not found"
  kill -KILL "$pid"
  wait "$job"
  rc=$?
  [ "$rc" -ne 0 ] && [ "$rc" -ne 124 ] || fail "exit code $rc (0: no error, 124: hung)"
  # (Open MPI 4.1 prints "PID 0" here: the pid is not checked.)
  grep -q "process rank 1 with PID [0-9]* on node .* exited on signal 9" "$work/run.err" \
    || fail "rank 1 and its signal not named"
  ;;
rank_error)
  mkdir -p "$work/used" && touch "$work/used/something"
  train used mpi --steps 1 && fail "a used run folder was accepted"
  grep -q "simpli: rank 0 of 2: error: run folder '.*used' already exists and is not empty; use --resume to continue it; ending all ranks" \
    "$work/used.err" || fail "no named error"
  ;;
*) fail "unknown case $case" ;;
esac
echo PASS
