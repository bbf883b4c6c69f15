#!/usr/bin/env python3
"""End-to-end test of scripts/weights-to-f32.py (a run's F64 averaged weights as shipped F32).

1. F64 weights (the shipped F32 weights widened to F64, one tensor given values off the F32
   grid) come back as F32: every tensor is its F64 values rounded to F32, bit for bit (so the
   widened shipped tensors are the shipped ones again), with the metadata kept.
2. `simpli eval` loads the result and scores exactly what the shipped weights score.
3. A value that is not finite in F32 (1e300) and the bad inputs and outputs every weights script
   refuses: a named error, exit 1, nothing written, the input untouched; --force replaces.

Usage: weights_to_f32.py SIMPLI SCRIPT WEIGHTS SCENE WORKDIR
"""
import json
import os
import re
import shutil
import struct
import subprocess
import sys

import numpy as np

from script_test_support import (check_force_replaces, check_weights_script_errors, fail,
                                 read_safetensors, run_script)

OFF_GRID = "rgba_decoder_lvl2.model.0.conv.bias"  # a tensor given values F32 cannot hold


def write_f64(weights, path, offset):
    """The weights as an F64 file; OFF_GRID gets F64 values off the F32 grid (+ offset)."""
    tensors, metadata = read_safetensors(weights)
    header, blobs, at = {"__metadata__": metadata}, [], 0
    for name, (dtype, shape, raw) in sorted(tensors.items()):
        if dtype != "F32":
            fail(f"{weights}: tensor {name} is {dtype}, expected the shipped F32")
        values = np.frombuffer(raw, dtype="<f4").astype("<f8")
        if name == OFF_GRID:
            values = values * (1 + 1e-6) + offset  # not on the F32 grid
        raw = values.tobytes()
        header[name] = {"dtype": "F64", "shape": shape, "data_offsets": [at, at + len(raw)]}
        blobs.append(raw)
        at += len(raw)
    text = json.dumps(header).encode()
    text += b" " * ((8 - len(text) % 8) % 8)
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)) + text + b"".join(blobs))


def check_cast(f64_path, out, weights):
    wide, wide_meta = read_safetensors(f64_path)
    cast, cast_meta = read_safetensors(out)
    shipped, _ = read_safetensors(weights)
    if cast_meta != wide_meta:
        fail(f"metadata changed: {cast_meta.keys()} against {wide_meta.keys()}")
    if sorted(cast) != sorted(wide):
        fail("tensor names differ")
    for name, (dtype, shape, raw) in cast.items():
        expected = np.frombuffer(wide[name][2], dtype="<f8").astype("<f4").tobytes()
        if dtype != "F32" or shape != wide[name][1] or raw != expected:
            fail(f"tensor {name}: {dtype} {shape}, not the F64 values rounded to F32")
        if name != OFF_GRID and raw != shipped[name][2]:
            fail(f"tensor {name}: not the shipped F32 values again")
    if cast[OFF_GRID][2] == shipped[OFF_GRID][2]:
        fail(f"{OFF_GRID}: the off-grid values rounded to the shipped ones (the test lost its case)")


def check_scores(simpli, weights, out, scene, work):
    run = subprocess.run(
        [simpli, "eval", scene, "--weights", f"{weights},{out}", "--views", "3", "--novel", "2",
         "--size", "96x64"], capture_output=True, text=True)
    log = run.stdout + run.stderr
    with open(os.path.join(work, "eval.txt"), "w") as f:
        f.write(log)
    if run.returncode != 0:
        fail(f"eval exited {run.returncode}:\n{log}")
    if not re.search(r"model 2 - model 1 +PSNR +[-+]0\.00 \+- 0\.00 dB", log):
        fail(f"the cast weights score differently from the shipped ones:\n{log}")


def main():
    if len(sys.argv) != 6:
        fail("usage: weights_to_f32.py SIMPLI SCRIPT WEIGHTS SCENE WORKDIR")
    simpli, script, weights, scene, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    f64_path, out = os.path.join(work, "f64.safetensors"), os.path.join(work, "f32.safetensors")
    write_f64(weights, f64_path, offset=1e-12)
    result = run_script(script, f64_path, out)
    if result.returncode != 0 or "201 tensors as F32" not in result.stdout:
        fail(f"cast exited {result.returncode}:\n{result.stdout}{result.stderr}")
    check_cast(f64_path, out, weights)
    # The shipped weights are F32 already: cast, they stay byte for byte the same tensors.
    again = os.path.join(work, "again.safetensors")
    if run_script(script, weights, again).returncode != 0:
        fail("casting F32 weights failed")
    if read_safetensors(again) != read_safetensors(weights):
        fail("F32 weights changed when cast to F32")
    check_scores(simpli, weights, out, scene, work)
    huge = os.path.join(work, "huge.safetensors")
    write_f64(weights, huge, offset=1e300)
    check_weights_script_errors(script, f64_path, out, work, extra_cases=[
        ("not_finite", [huge, f"{work}/h.safetensors"], rf"'{OFF_GRID}' has values that are not "
         "finite in F32", "h.safetensors")])
    check_force_replaces(script, f64_path, out)
    print("PASS")


if __name__ == "__main__":
    main()
