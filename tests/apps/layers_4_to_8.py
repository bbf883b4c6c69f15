#!/usr/bin/env python3
"""End-to-end test of scripts/layers-4-to-8.py (4-layer weights as a start for SIMPLI-8L).

1. The shipped 4-layer weights convert: every tensor but the three the conversion is about comes
   back bit for bit; each anchor is there twice (within the documented 1e-3 x RMS of noise, and
   the copies differ); the depth decoder keeps group logits 0, 2, 4; the metadata's network is
   model/configs/tiny-prior-8l.json.
2. `simpli eval` loads the result as an 8-layer network and scores it near the 4-layer one on a
   bundled scene (the conversion is a start for fine-tuning, not a scrambled network).
3. Bad input and outputs: a named error, exit 1, nothing written, the input untouched; --force
   replaces an earlier output.

Usage: layers_4_to_8.py SIMPLI SCRIPT WEIGHTS CONFIG_DIR SCENE WORKDIR
"""
import json
import os
import re
import shutil
import subprocess
import sys

import numpy as np

from script_test_support import (check_force_replaces, check_weights_script_errors, fail,
                                 read_safetensors, run_script)

CHANGED = ("planes_deformer_lvl1.anchor", "depth_decoder_lvl1.model.2.conv.weight",
           "depth_decoder_lvl1.model.2.conv.bias")
DTYPES = {"F32": "<f4", "F64": "<f8"}


def read_arrays(path):
    """({name: NumPy array}, metadata) of a safetensors file of F32/F64 tensors."""
    tensors, metadata = read_safetensors(path)
    return {name: np.frombuffer(raw, dtype=DTYPES[dtype]).reshape(shape)
            for name, (dtype, shape, raw) in tensors.items()}, metadata


def check_conversion(weights, out, configs):
    src, _ = read_arrays(weights)
    dst, meta = read_arrays(out)
    if sorted(src) != sorted(dst):
        fail(f"tensor names differ: {sorted(set(src) ^ set(dst))}")
    for name in src:
        if name in CHANGED:
            continue
        if src[name].dtype != dst[name].dtype or not np.array_equal(src[name], dst[name]):
            fail(f"tensor {name} changed")
    anchor, anchor8 = src[CHANGED[0]], dst[CHANGED[0]]
    if anchor8.shape != (8,) + anchor.shape[1:]:
        fail(f"anchor shape {anchor8.shape}, expected (8,) + {anchor.shape[1:]}")
    rms = float(np.sqrt((anchor.astype(np.float64) ** 2).mean()))
    offset = np.abs(anchor8 - np.repeat(anchor, 2, axis=0))
    if offset.max() > 6e-3 * rms or offset.max() == 0:
        fail(f"anchor copies are {offset.max()} away from the originals (RMS {rms}): "
             "expected noise of 1e-3 x RMS, not none")
    if np.array_equal(anchor8[0::2], anchor8[1::2]):
        fail("the two copies of each anchor are equal: they cannot learn apart")
    for name in CHANGED[1:]:
        if not np.array_equal(dst[name], src[name][[0, 2, 4]]):
            fail(f"{name}: not the 4-layer network's group logits 0, 2, 4")
    config = json.loads(meta["network_config"])
    with open(os.path.join(configs, "tiny-prior-8l.json")) as f:
        expected = json.load(f)
    if config != expected:
        fail(f"metadata network config differs from tiny-prior-8l.json: {config}")


def check_scores(simpli, weights, out, scene, work):
    eval_run = subprocess.run(
        [simpli, "eval", scene, "--weights", f"{weights},{out}", "--views", "3", "--novel", "2",
         "--repeats", "2", "--size", "96x64"], capture_output=True, text=True)
    log = eval_run.stdout + eval_run.stderr
    with open(os.path.join(work, "eval.txt"), "w") as f:
        f.write(log)
    if eval_run.returncode != 0:
        fail(f"eval exited {eval_run.returncode}:\n{log}")
    scores = re.findall(r"model (\d) +PSNR +([0-9.]+) \+-", log)
    if len(scores) != 2:
        fail(f"expected two scores:\n{log}")
    psnr4, psnr8 = float(scores[0][1]), float(scores[1][1])
    print(f"bundled scene: 4 layers {psnr4:.2f} dB, converted to 8 layers {psnr8:.2f} dB")
    # Measured 30.4 -> 30.3 dB. A conversion that scrambles layers or logits costs several dB.
    if abs(psnr8 - psnr4) > 1.0:
        fail(f"the converted network scores {psnr8} dB against {psnr4}")
    if "8 layers" not in log and "tiny-prior-8l" not in log:
        fail(f"eval did not load an 8-layer network:\n{log}")


def main():
    if len(sys.argv) != 7:
        fail("usage: layers_4_to_8.py SIMPLI SCRIPT WEIGHTS CONFIG_DIR SCENE WORKDIR")
    simpli, script, weights, configs, scene, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    out = os.path.join(work, "8l.safetensors")
    result = run_script(script, weights, out)
    if result.returncode != 0 or not os.path.isfile(out):
        fail(f"conversion exited {result.returncode}:\n{result.stdout}{result.stderr}")
    check_conversion(weights, out, configs)
    check_scores(simpli, weights, out, scene, work)
    check_weights_script_errors(script, weights, out, work, extra_cases=[
        ("eight", [out, f"{work}/e.safetensors"], r"num_layers 8.*expected 4", "e.safetensors")])
    check_force_replaces(script, weights, out)
    check_conversion(weights, out, configs)
    print("PASS")


if __name__ == "__main__":
    main()
