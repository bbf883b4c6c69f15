#!/bin/bash
# `simpli infer` cancelled by a signal during the forward pass: it stops after the current stage,
# exits with 128 + signal (130 SIGINT, 143 SIGTERM), says so, and writes nothing.
# Usage: infer_signal.sh SIMPLI SCENE WORKDIR INT|TERM
set -u
simpli=$1 scene=$2 work=$3 sig=$4
fail() { echo "FAIL: $*"; for f in "$work"/out "$work"/err; do echo "--- $f"; cat "$f"; done; exit 1; }
rm -rf "$work" && mkdir -p "$work" || exit 1
out="$work/mli"

# official-4l with random weights on every view: many seconds of forward pass on a CPU device.
"$simpli" infer "$scene" --config official-4l --init-random 1 --out "$out" \
  > "$work/out" 2> "$work/err" &
pid=$!
# The progress bar's first line (plain mode: stderr is a file) marks the first finished stage.
for _ in $(seq 1 1200); do
  grep -q "^forward 1/" "$work/err" 2> /dev/null && break
  kill -0 "$pid" 2> /dev/null || fail "infer exited before its first stage"
  sleep 0.1
done
grep -q "^forward 1/" "$work/err" || fail "no progress line in time"
kill -"$sig" "$pid"
wait "$pid"
rc=$?
if [ "$sig" = INT ]; then expect=130; else expect=143; fi
[ "$rc" -eq "$expect" ] || fail "exit code $rc, expected $expect"
grep -q "SIG$sig received; cancelled, nothing written to $out" "$work/err" \
  || fail "no cancel message on stderr"
[ ! -e "$out" ] || fail "$out was written"
echo "PASS"
