#!/usr/bin/env bash
# The main job (README): install missing packages, build, then run simpli on this machine.
# Until the SIMPLI network lands this runs the engine self-check and the op benchmark.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SIMPLI_BUILD_DIR:-$root/build}
bash "$root/scripts/install-deps.sh"
bash "$root/scripts/build.sh"
simpli="$build/bin/simpli"
echo "== simpli devices --check (engine self-check)"
"$simpli" devices --check
echo "== simpli bench ops (engine benchmark against OpenBLAS on the same cores)"
"$simpli" bench ops
