#!/usr/bin/env bash
# The training step of two builds on the same machine, runs alternating so that both see the
# same load (issue 10 item 4: "2x faster than today on the same machine"):
#   bash scripts/bench-train-ab.sh OLD_SIMPLI NEW_SIMPLI RUNS [bench train options...]
# e.g. an older commit built beside the tree:
#   git worktree add ../bench-old b4c0202 && cmake -S ../bench-old -B ../bench-old/build \
#     -DSIMPLI_WITH_VTK=OFF -DSIMPLI_USE_MPI=OFF && cmake --build ../bench-old/build --target simpli
#   bash scripts/bench-train-ab.sh ../bench-old/build/bin/simpli build/bin/simpli 3 \
#     --config tiny-world --size 128x96 --steps 6
# Each run is one `simpli bench train` (a warm-up step, then the timed steps); the old build goes
# first in odd runs and second in even ones. Prints every run's mean, then the mean of the runs'
# means per build and their ratio, and the new build's GEMM backend line (its OpenBLAS kernel).
# OPENBLAS_CORETYPE / OPENBLAS_L2_SIZE are unset for the benchmark processes only (they force a
# slower OpenBLAS kernel on this kind of machine; builds before bench train re-executed itself
# without them get them unset here). Stop training runs first (kill -STOP) for figures of a
# quiet machine.
set -euo pipefail
old=${1:?usage: bench-train-ab.sh OLD_SIMPLI NEW_SIMPLI RUNS [bench train options...]}
new=${2:?usage: bench-train-ab.sh OLD_SIMPLI NEW_SIMPLI RUNS [bench train options...]}
runs=${3:?usage: bench-train-ab.sh OLD_SIMPLI NEW_SIMPLI RUNS [bench train options...]}
shift 3
for b in "$old" "$new"; do
  [[ -x "$b" ]] || { echo "bench-train-ab.sh: '$b' is not an executable" >&2; exit 2; }
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "bench-train-ab.sh: RUNS '$runs' is not a positive count" >&2; exit 2; }
declare -a old_ms new_ms
time_build() { # BINARY -> mean ms of one bench train run
  local bin=$1 out
  shift
  out=$(env -u OPENBLAS_CORETYPE -u OPENBLAS_L2_SIZE "$bin" bench train "$@" 2>&1) || {
    echo "$out" >&2
    exit 1
  }
  echo "$out" | grep "^gemm backend" >&2 || true
  echo "$out" | sed -n 's/^train step: \([0-9]*\) +- \([0-9]*\) ms.*load average \(.*\)$/\1 \2 \3/p'
}
for ((r = 1; r <= runs; ++r)); do
  if ((r % 2)); then order=(old new); else order=(new old); fi
  for which in "${order[@]}"; do
    bin=$old
    [[ $which == new ]] && bin=$new
    # A plain substitution, not < <(...): a failed bench train stops the script (set -e)
    # instead of being read as an empty (zero) time.
    line=$(time_build "$bin" "$@")
    read -r mean std load <<< "$line"
    [[ -n "${mean:-}" ]] || { echo "bench-train-ab.sh: no 'train step:' line from $bin" >&2; exit 1; }
    printf 'run %d %-3s %6d +- %5d ms/step (load %s)\n' "$r" "$which" "$mean" "$std" "$load"
    if [[ $which == old ]]; then old_ms+=("$mean"); else new_ms+=("$mean"); fi
  done
done
python3 - "${#old_ms[@]}" "${old_ms[@]}" "${new_ms[@]}" <<'EOF'
import statistics as st, sys
n = int(sys.argv[1]); v = [float(x) for x in sys.argv[2:]]
old, new = v[:n], v[n:]
sd = lambda x: st.stdev(x) if len(x) > 1 else 0.0
print(f"old: {st.mean(old):.0f} +- {sd(old):.0f} ms/step, new: {st.mean(new):.0f} +- {sd(new):.0f} "
      f"ms/step (means of {n} runs); new/old {st.mean(new) / st.mean(old):.2f} "
      f"({st.mean(old) / st.mean(new):.2f}x faster); per run: "
      + ", ".join(f"{b / a:.2f}" for a, b in zip(old, new)))
EOF
