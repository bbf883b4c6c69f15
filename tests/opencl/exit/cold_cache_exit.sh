#!/usr/bin/env bash
# Processes that end with engine work in flight, each with an EMPTY PoCL kernel cache (as on a
# fresh machine), must exit with their own exit code, not SIGSEGV (139). Issue 9: PoCL compiles
# a kernel at its first launch on a worker thread; exiting during that compile crashed in LLVM's
# static destructors. Cases: exit_with_work_in_flight ending by return / exit / quick_exit (0),
# a caught error (1), a handled SIGTERM (143), a partly warm cache (0); `simpli devices --check`
# and `simpli infer` on a bundled scene (0). No case may print the kernel compiler's warnings
# ("1 warning generated.", a 16-wide vector load in conv_direct once did). Cold compiles dominate (~20 s CPU per process, most
# of it building CLBlast's GEMM program), so two cases run at a time: ~190 s CPU in all.
# Usage: cold_cache_exit.sh EXIT_WITH_WORK_IN_FLIGHT SIMPLI SCENE
set -u
program=$1 simpli=$2 scene=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cases=0

# check ID NAME EXPECTED CACHE COMMAND...: runs COMMAND with POCL_CACHE_DIR=CACHE and writes one
# result line (and the output's tail on failure) to $work/result.ID.
check() {
  local id=$1 name=$2 expected=$3 cache=$4
  shift 4
  local start=$SECONDS rc
  POCL_CACHE_DIR=$cache "$@" > "$work/out.$id" 2>&1
  rc=$?
  if grep -q "warnings\? generated" "$work/out.$id"; then
    # The OpenCL C compiler's diagnostics reach the user's terminal on a cold cache.
    {
      echo "FAIL $name: kernel compiler warnings on a cold cache; output:"
      grep -B2 "warnings\? generated" "$work/out.$id" | tail -n 20
    } >> "$work/result.$id"
  elif [ "$rc" -eq "$expected" ]; then
    echo "ok   $name: exit $rc ($((SECONDS - start)) s)" >> "$work/result.$id"
  else
    {
      echo "FAIL $name: exit $rc, expected $expected ($((SECONDS - start)) s); output:"
      tail -n 20 "$work/out.$id"
    } >> "$work/result.$id"
  fi
}

# Return from main with an empty cache, then, with the cache that run filled, a run that adds
# other kernels and shapes (a partly warm cache).
returnThenPartlyWarm() {
  local id=$1 cache
  cache=$(mktemp -d -p "$work" cache.XXXXXX)
  check "$id" "return from main" 0 "$cache" "$program" return
  check "$id" "partly warm cache" 0 "$cache" "$program" return more
  rm -rf "$cache"
}

# start FUNCTION NAME ...: runs a case in the background, at most two at a time.
start() {
  while [ "$(jobs -rp | wc -l)" -ge 2 ]; do
    wait -n
  done
  local fn=$1
  shift
  cases=$((cases + 1))
  "$fn" "$cases" "$@" &
}

# cold_case ID NAME EXPECTED COMMAND...: check with a fresh, empty cache.
cold_case() {
  local id=$1 name=$2 expected=$3 cache
  shift 3
  cache=$(mktemp -d -p "$work" cache.XXXXXX)
  check "$id" "$name" "$expected" "$cache" "$@"
  rm -rf "$cache"
}

# The longest cases first.
start cold_case "simpli devices --check" 0 "$simpli" devices --check
# The small test network with random weights on three views of the bundled 192 x 128 scene.
start cold_case "simpli infer" 0 "$simpli" infer "$scene" --config tiny --init-random 3 \
  --views 0,2,4 --layers auto --out "$work/mli"
start returnThenPartlyWarm
start cold_case "exit(0)" 0 "$program" exit
start cold_case "quick_exit(0)" 0 "$program" quick_exit
start cold_case "caught error" 1 "$program" error
start cold_case "handled SIGTERM" 143 "$program" sigterm
wait

failures=0
for id in $(seq 1 "$cases"); do
  if [ ! -f "$work/result.$id" ]; then
    echo "FAIL case $id wrote no result"
    failures=$((failures + 1))
    continue
  fi
  cat "$work/result.$id"
  failures=$((failures + $(grep -c "^FAIL" "$work/result.$id")))
done
if [ "$failures" -ne 0 ]; then
  echo "FAIL: $failures case(s)"
  exit 1
fi
echo "PASS"
