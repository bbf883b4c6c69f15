#!/usr/bin/env bash
# Tunes CLBlast's GEMM kernels for one OpenCL device and writes simpli's tuning table for it
# (opencl/tuning/<device>.json), which the build embeds and Device applies at start-up through
# clblast::OverrideParameters. See docs/clblast_tuning.md.
#
# Usage: scripts/tune_clblast.sh [options]
#   -p, --platform N     OpenCL platform index (default 0; as listed by `clinfo -l`)
#   -d, --device N       device index on that platform (default 0)
#   -w, --workdir DIR    where the tuners run and leave their JSON (default /tmp/simpli_clblast_tuning)
#   -o, --out DIR        table directory (default: opencl/tuning next to this script)
#   -s, --size N         m = n = k of the Xgemm kernel tuning (default 512, a multiple of 128)
#   --precisions "P..."  precisions to tune, 32 and/or 64 (default "32 64")
#   --skip-routine       skip the direct/indirect switch-point tuning (clblast_tuner_routine_xgemm)
#   --routine-only       only (re)tune the direct/indirect switch point, from the kernel results
#                        already in the workdir, then convert
#   --convert-only       do not run tuners, only convert the JSON already in the workdir
# Needs the Debian package clblast-utils (the clblast_tuner_* programs) and python3.
# The tuners take minutes to an hour; run it on an otherwise idle machine, because the tuners
# pick parameters by timing and a busy CPU distorts their choice.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
platform=0
device=0
workdir=/tmp/simpli_clblast_tuning
out="${here}/../opencl/tuning"
size=512
precisions="32 64"
run_tuners=1
run_routine=1
run_kernels=1

usage() { sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'; }

while [[ $# -gt 0 ]]; do
  case "$1" in
    -p | --platform) platform="$2"; shift 2 ;;
    -d | --device) device="$2"; shift 2 ;;
    -w | --workdir) workdir="$2"; shift 2 ;;
    -o | --out) out="$2"; shift 2 ;;
    -s | --size) size="$2"; shift 2 ;;
    --precisions) precisions="$2"; shift 2 ;;
    --skip-routine) run_routine=0; shift ;;
    --routine-only) run_kernels=0; shift ;;
    --convert-only) run_tuners=0; shift ;;
    -h | --help) usage; exit 0 ;;
    *) echo "tune_clblast.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done

for value in "$platform" "$device" "$size"; do
  if ! [[ "$value" =~ ^[0-9]+$ ]]; then
    echo "tune_clblast.sh: expected a non-negative integer, got '$value'" >&2
    exit 2
  fi
done
if (( size % 128 != 0 )); then
  echo "tune_clblast.sh: --size $size must be a multiple of 128 (Xgemm tuner constraint)" >&2
  exit 2
fi
for p in $precisions; do
  if [[ "$p" != 32 && "$p" != 64 ]]; then
    echo "tune_clblast.sh: precision '$p' is not 32 or 64" >&2
    exit 2
  fi
done
command -v python3 > /dev/null || { echo "tune_clblast.sh: python3 is required" >&2; exit 1; }

mkdir -p "$workdir" "$out"
workdir="$(cd "$workdir" && pwd)"
cd "$workdir"

tune() { # tuner-name log-name args...
  local tuner="clblast_tuner_$1" log="$workdir/$2.log"
  shift 2
  if ! command -v "$tuner" > /dev/null; then
    echo "tune_clblast.sh: $tuner not found; install the Debian package clblast-utils" >&2
    exit 1
  fi
  echo "[$(date +%T)] $tuner $* (log: $log)"
  "$tuner" -platform "$platform" -device "$device" "$@" > "$log" 2>&1 || {
    echo "tune_clblast.sh: $tuner failed, see $log" >&2
    exit 1
  }
}

convert() { # writes the table; with --routine-input DIR also tuner-format best-of files there
  python3 - "$workdir" "$out" "$@" << 'PYTHON'
import glob, json, os, re, sys

workdir, out = sys.argv[1], sys.argv[2]
routine_dir = sys.argv[4] if len(sys.argv) > 4 and sys.argv[3] == "--routine-input" else None

# Tuner kernel_family -> the kernel name clblast::OverrideParameters expects.
def kernel_of(family):
    if re.fullmatch(r"xgemm_\d+", family): return "Xgemm"
    if re.fullmatch(r"xgemm_direct_\d+", family): return "XgemmDirect"
    return {"copy": "Copy", "pad": "Pad", "transpose": "Transpose",
            "padtranspose": "Padtranspose", "gemm_routine": "GemmRoutine",
            "xconvgemm": "Xconvgemm"}.get(family)

best = {}  # (kernel, precision) -> entry
meta = {}
for path in sorted(glob.glob(os.path.join(workdir, "clblast_*.json"))):
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"tune_clblast.sh: cannot read {path}: {e}")
    family = data.get("kernel_family", "")
    # GEMMK=1 Xgemm variants (tuner stages xgemm_11/xgemm_12) give wrong results in CLBlast
    # 1.5's batched GEMM (GemmStridedBatched), which simpli uses; only GEMMK=0 is kept.
    if family in ("xgemm_11", "xgemm_12"):
        continue
    kernel = kernel_of(family)
    if kernel is None or "best_parameters" not in data:
        continue
    precision = int(data["precision"])
    params = {}
    for item in data["best_parameters"].split():
        name, _, value = item.partition("=")
        if name != "PRECISION":
            params[name] = int(value)
    # The routine tuner's "best_time" is a score, not a time; every other tuner reports ms
    # for the same problem within a family, so the fastest family wins.
    time = float(data.get("best_time", "inf"))
    entry = {"kernel": kernel, "precision": precision, "parameters": params,
             "tuner": family, "best_time_ms": time if kernel != "GemmRoutine" else None}
    key = (kernel, precision)
    if key not in best or (entry["best_time_ms"] is not None and
                           best[key]["best_time_ms"] is not None and
                           time < best[key]["best_time_ms"]):
        best[key] = entry
    for field in ("device", "clblast_device_name", "device_vendor", "platform_version",
                  "device_type", "device_compute_units"):
        if field in data:
            meta[field] = data[field]

if not best:
    sys.exit(f"tune_clblast.sh: no tuner results (clblast_*.json) in {workdir}")
name = meta.get("clblast_device_name") or meta.get("device")
table = {
    "format": "simpli-clblast-tuning/1",
    "clblast_device_name": name,
    "opencl_device_names": [meta.get("device", name)],
    "device_vendor": meta.get("device_vendor", ""),
    "device_type": meta.get("device_type", ""),
    "compute_units": int(meta.get("device_compute_units", "0") or 0),
    "platform_version": meta.get("platform_version", ""),
    "kernels": [best[k] for k in sorted(best)],
}
stem = re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_")
target = os.path.join(out, stem + ".json")
with open(target + ".tmp", "w") as f:
    json.dump(table, f, indent=2)
    f.write("\n")
os.replace(target + ".tmp", target)
print(f"wrote {target}:")
for e in table["kernels"]:
    params = " ".join(f"{k}={v}" for k, v in sorted(e["parameters"].items()))
    print(f"  {e['kernel']:<13} fp{e['precision']}  {params}  (from {e['tuner']})")

# The routine tuner reads the kernels' best parameters from tuner-format files named after the
# first family (xgemm_1, xgemm_direct_1, ...) in its working directory; give it the overall best.
if routine_dir:
    os.makedirs(routine_dir, exist_ok=True)
    families = {"Xgemm": "xgemm_1", "XgemmDirect": "xgemm_direct_1", "Copy": "copy",
                "Pad": "pad", "Transpose": "transpose", "Padtranspose": "padtranspose"}
    for (kernel, precision), e in best.items():
        if kernel not in families:
            continue
        params = " ".join(f"{k}={v}" for k, v in sorted(e["parameters"].items()))
        path = os.path.join(routine_dir, f"clblast_{families[kernel]}_{precision}.json")
        with open(path, "w") as f:
            f.write("{\n")
            f.write(f"  \"kernel_family\": \"{families[kernel]}\",\n")
            # CLBlast reads these files line by line and expects the tuner's exact layout:
            # two-space indent, one field per line, a comma after each value but the last.
            f.write(f"  \"best_parameters\": \"{params} PRECISION={precision}\",\n")
            f.write(f"  \"precision\": \"{precision}\"\n")
            f.write("}\n")
PYTHON
}

if (( run_tuners )); then
  for p in $precisions; do
    (( run_kernels )) || break
    tune xgemm "xgemm_$p" -precision "$p" -m "$size" -n "$size" -k "$size"
    tune xgemm_direct "xgemm_direct_$p" -precision "$p"
    tune copy_fast "copy_$p" -precision "$p"
    tune copy_pad "pad_$p" -precision "$p"
    tune transpose_fast "transpose_$p" -precision "$p"
    tune transpose_pad "padtranspose_$p" -precision "$p"
  done
  if (( run_routine )); then
    # The switch point between XgemmDirect and the indirect Xgemm path depends on the tuned
    # kernels, so it is tuned last, with the best kernel parameters preloaded.
    convert --routine-input "$workdir/routine"
    for p in $precisions; do
      (cd "$workdir/routine" && tune routine_xgemm "routine_$p" -precision "$p" -runs 3)
      cp "$workdir/routine/clblast_gemm_routine_$p.json" "$workdir/"
    done
  fi
fi
convert
