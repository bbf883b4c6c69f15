#!/usr/bin/env bash
# The test command (README, .ci/run): install missing packages, configure, build, run ctest.
# Tests that render need X: the whole ctest runs under xvfb-run. Tests labelled "slow" run
# only with SIMPLI_TEST_SLOW=1.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SIMPLI_BUILD_DIR:-$root/build}
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/build.sh"
exclude=(-LE slow)
[[ "${SIMPLI_TEST_SLOW:-0}" == 1 ]] && exclude=()
xvfb-run -a -s "-screen 0 1024x768x24 -noreset" \
  ctest --test-dir "$build" --output-on-failure --timeout 1500 -j"${SIMPLI_JOBS:-2}" "${exclude[@]}" "$@"
