#!/usr/bin/env bash
# The test command (README, .ci/run): install missing packages, configure, build, run ctest.
# Tests that render need X: the whole ctest runs under xvfb-run. Tests labelled "slow" run
# only with SIMPLI_TEST_SLOW=1. The tests use an empty PoCL kernel cache of their own, so that CI
# tests what a fresh machine runs (issue 9: exit-time crashes appeared only with a cold cache);
# the run's processes share it, so each kernel compiles once per run. For quicker local re-runs,
# SIMPLI_TEST_POCL_CACHE=DIR keeps and reuses a cache there (not what CI does).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SIMPLI_BUILD_DIR:-$root/build}
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/build.sh"
exclude=(-LE slow)
[[ "${SIMPLI_TEST_SLOW:-0}" == 1 ]] && exclude=()
if [[ -n "${SIMPLI_TEST_POCL_CACHE:-}" ]]; then
  mkdir -p "$SIMPLI_TEST_POCL_CACHE"
  export POCL_CACHE_DIR=$SIMPLI_TEST_POCL_CACHE
else
  pocl_cache=$(mktemp -d -t simpli-pocl-cache.XXXXXX)
  trap 'rm -rf "$pocl_cache"' EXIT
  export POCL_CACHE_DIR=$pocl_cache
fi
xvfb-run -a -s "-screen 0 1024x768x24 -noreset" \
  ctest --test-dir "$build" --output-on-failure --timeout 1500 -j"${SIMPLI_JOBS:-2}" "${exclude[@]}" "$@"
