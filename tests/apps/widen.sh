#!/bin/bash
# `simpli widen` end to end: tiny weights widened x2 score exactly what they scored on a
# bundled scene (paired eval, and with the shipped tiny-x2 config file), and every bad option or
# output gets a named error with nothing written and the input untouched.
# Usage: widen.sh SIMPLI WEIGHTS SCENE CONFIG_DIR WORKDIR
set -u
simpli=$1 weights=$2 scene=$3 configs=$4 work=$5
fail() {
  echo "FAIL: $*"
  for f in "$work"/*.txt; do [ -f "$f" ] && { echo "--- $f"; cat "$f"; }; done
  exit 1
}
rm -rf "$work" && mkdir -p "$work" || exit 1
input_sum=$(md5sum < "$weights")
wide=$work/wide.safetensors

# Widen, then the same scores on the same samples.
"$simpli" widen --weights "$weights" --out "$wide" --config-out "$work/wide.json" \
  > "$work/widen.txt" 2>&1 || fail "widen exited $?"
grep -q "config tiny, 204329 parameters) x2 -> .*config tiny-x2, 690685 parameters" \
  "$work/widen.txt" || fail "unexpected widen summary"
[ -f "$wide" ] && [ -f "$work/wide.json" ] || fail "outputs missing"
"$simpli" eval "$scene" --weights "$weights,$wide" --views 3 --novel 2 --repeats 2 --size 96x64 \
  > "$work/eval.txt" 2>&1 || fail "eval exited $?"
grep -qE "model 2 - model 1 +PSNR +[-+]0\.00 \+- 0\.00 dB" "$work/eval.txt" ||
  fail "the widened network scores differently"
grep -qE "model 1 +PSNR +[0-9]+\.[0-9]+" "$work/eval.txt" || fail "no score"
# The shipped config file is the one widen writes (eval with it loads the weights).
"$simpli" eval "$scene" --weights "$wide" --config "$configs/tiny-x2.json" --views 2 --novel 1 \
  --size 96x64 > "$work/eval_config.txt" 2>&1 || fail "eval with tiny-x2.json exited $?"

# Bad input: a named error, exit 1, nothing written, the input untouched.
wide_sum=$(md5sum < "$wide")
expect_error() { # NAME REGEX ARGS...
  local name=$1 regex=$2
  shift 2
  "$simpli" widen "$@" > "$work/$name.txt" 2>&1
  local rc=$?
  [ $rc -eq 1 ] || fail "$name: exit $rc, expected 1"
  grep -qE -- "$regex" "$work/$name.txt" || fail "$name: no error matching '$regex'"
}
expect_error exists "--out .*wide.safetensors already exists \(use --force" \
  --weights "$weights" --out "$wide"
expect_error input "is the input weights; refusing" --weights "$weights" --out "$weights" --force
expect_error folder "--out .* is a folder" --weights "$weights" --out "$work"
expect_error no_parent "its folder .*/missing does not exist" \
  --weights "$weights" --out "$work/missing/w.safetensors"
expect_error factor "factor 1 must be between 2 and 8" \
  --weights "$weights" --out "$work/f.safetensors" --factor 1
expect_error noise "noise -1 must be finite and >= 0" \
  --weights "$weights" --out "$work/n.safetensors" --noise -1
expect_error missing "no/such.safetensors" --weights /no/such.safetensors --out "$work/m.safetensors"
[ "$(md5sum < "$weights")" == "$input_sum" ] || fail "the input weights changed"
[ "$(md5sum < "$wide")" == "$wide_sum" ] || fail "an earlier output changed"
for f in f n m w; do [ ! -e "$work/$f.safetensors" ] || fail "$f.safetensors was written"; done
[ -z "$(ls -A "$work" | grep '^\.')" ] || fail "hidden leftovers in $work"
# --force replaces an earlier output (a different seed: different perturbation).
"$simpli" widen --weights "$weights" --out "$wide" --seed 5 --force > "$work/force.txt" 2>&1 ||
  fail "widen --force exited $?"
[ "$(md5sum < "$wide")" != "$wide_sum" ] || fail "--force did not replace the output"
echo PASS
