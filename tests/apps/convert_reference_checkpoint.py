#!/usr/bin/env python3
"""End-to-end test of scripts/convert_reference_checkpoint.py (needs PyTorch; skipped without).

1. `simpli infer --config official-4l --init-random` builds an MLI with random weights and saves
   them (reference key names).
2. Those tensors are wrapped the way the reference trainer saves a generator checkpoint
   (`module.` prefixes from DataParallel, the state dict under an entry of a larger dict, some
   tensors in float16/float64) and written with torch.save.
3. The converter turns the .pt back into safetensors: every tensor must come back bit for bit
   (the float16 ones: exactly their float16 value), with config official-4l in the metadata.
4. Converted float32 weights, given to `simpli infer` (config from the metadata), must build the
   same lossless MLI as step 1, byte for byte.
5. Bad checkpoints fail with a message and leave no output file.

Usage: convert_reference_checkpoint.py SIMPLI CONVERTER SCENE WORKDIR
"""
import collections
import filecmp
import os
import shutil
import subprocess
import sys

from script_test_support import fail, read_safetensors

SKIP = 77  # ctest SKIP_RETURN_CODE


def run(command, expect_ok=True):
    print("$ " + " ".join(command), flush=True)
    result = subprocess.run(command, capture_output=True, text=True)
    print(result.stdout + result.stderr, flush=True)
    if expect_ok and result.returncode != 0:
        fail(f"exit code {result.returncode}")
    return result


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    simpli, converter, scene, work = sys.argv[1:]
    try:
        import torch
    except ImportError:
        print("SKIP: PyTorch is not installed (Debian: python3-torch)")
        return SKIP

    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    infer = [simpli, "infer", scene, "--views", "0,4", "--corrections", "1"]

    # 1. Random official-4l weights and the MLI they build.
    run(infer + ["--config", "official-4l", "--init-random", "7", "--out", f"{work}/random"])
    original, _ = read_safetensors(f"{work}/random/random_weights.safetensors")
    if "planes_deformer_lvl1.anchor" not in original or len(original) < 200:
        fail(f"unexpected random weights: {len(original)} tensors")

    # 2. A reference-style checkpoint.
    state = collections.OrderedDict()
    halves = set()
    for i, (name, (dtype, shape, raw)) in enumerate(sorted(original.items())):
        if dtype != "F32":
            fail(f"{name}: dtype {dtype}")
        t = torch.frombuffer(bytearray(raw), dtype=torch.float32).reshape(shape).clone()
        if i % 17 == 3:  # some tensors stored in other float types
            t = t.to(torch.float16)
            halves.add(name)
        elif i % 17 == 5:
            t = t.to(torch.float64)
        state["module." + name] = t
    checkpoint = {"iteration": 660000, "optimizer": {"lr": 3e-4}, "gen": state}
    pt = f"{work}/model.gen_00660000.pt"
    torch.save(checkpoint, pt)

    # 3. Convert and compare tensor by tensor.
    converted_path = f"{work}/converted.safetensors"
    out = run([sys.executable, converter, pt, converted_path]).stdout
    if "config official-4l" not in out:
        fail("the converter did not report config official-4l")
    converted, metadata = read_safetensors(converted_path)
    if metadata.get("config") != "official-4l":
        fail(f"metadata config {metadata.get('config')!r}")
    if sorted(converted) != sorted(original):
        fail("tensor names differ: " + str(set(converted) ^ set(original)))
    for name, (dtype, shape, raw) in original.items():
        c_dtype, c_shape, c_raw = converted[name]
        if c_dtype != "F32" or c_shape != shape:
            fail(f"{name}: {c_dtype} {c_shape}, expected F32 {shape}")
        expected = raw
        if name in halves:
            t = torch.frombuffer(bytearray(raw), dtype=torch.float32)
            expected = t.to(torch.float16).to(torch.float32).numpy().tobytes()
        if c_raw != expected:
            fail(f"{name}: values differ")
    if int(metadata.get("n_parameters", -1)) != sum(len(r) // 4 for _, _, r in original.values()):
        fail(f"n_parameters {metadata.get('n_parameters')}")

    # 4. A float32 state dict (bare, without prefixes: the other layout the converter accepts)
    # converts to weights that build exactly the MLI of step 1.
    plain = collections.OrderedDict(
        (n, torch.frombuffer(bytearray(raw), dtype=torch.float32).reshape(shape).clone())
        for n, (_, shape, raw) in sorted(original.items()))
    torch.save(plain, f"{work}/plain.pt")
    run([sys.executable, converter, f"{work}/plain.pt", f"{work}/plain.safetensors"])
    run(infer + ["--weights", f"{work}/plain.safetensors", "--out", f"{work}/plain"])
    expected_dir, actual_dir = f"{work}/random/lossless", f"{work}/plain/lossless"
    names = sorted(os.listdir(expected_dir))
    if not names or names != sorted(os.listdir(actual_dir)):
        fail(f"MLI files {sorted(os.listdir(actual_dir))}, expected {names}")
    _, mismatch, errors = filecmp.cmpfiles(expected_dir, actual_dir, names, shallow=False)
    if mismatch or errors:
        fail(f"the converted weights build a different MLI: {mismatch + errors}")

    # 5. Bad checkpoints: a message, a non-zero exit, no output file.
    bad_cases = [
        ({"gen": {"module.some.weight": torch.zeros(3)}}, "planes_deformer_lvl1.anchor"),
        ({"iteration": 5, "optimizer": {}}, "no state dict found"),
        ([1, 2, 3], "not a dict"),
        ({"module.x": torch.zeros(2), "x": torch.ones(2)}, "both with and without"),
        ({"planes_deformer_lvl1.anchor": torch.zeros(4, 16), "n": torch.zeros(2, dtype=torch.int64)},
         "expected floating point"),
        ({"planes_deformer_lvl1.anchor": torch.zeros(5, 16)}, "5 anchors"),
    ]
    for i, (content, message) in enumerate(bad_cases):
        path = f"{work}/bad_{i}.pt"
        torch.save(content, path)
        target = f"{work}/bad_{i}.safetensors"
        result = run([sys.executable, converter, path, target], expect_ok=False)
        if result.returncode == 0 or message not in result.stderr:
            fail(f"bad checkpoint {i}: expected an error containing {message!r}")
        if os.path.exists(target) or os.path.exists(target + ".tmp"):
            fail(f"bad checkpoint {i}: an output file was written")
    with open(f"{work}/text.pt", "w") as f:
        f.write("not a checkpoint\n")
    for name in ("no_such.pt", "text.pt"):
        result = run([sys.executable, converter, f"{work}/{name}", f"{work}/x.safetensors"],
                     expect_ok=False)
        if (result.returncode == 0 or f"{name}: cannot read the checkpoint" not in result.stderr
                or "Traceback" in result.stderr or os.path.exists(f"{work}/x.safetensors")):
            fail(f"{name}: expected one error line naming the file")
    # --key picks an entry; a wrong one is named.
    result = run([sys.executable, converter, pt, f"{work}/key.safetensors", "--key", "optimizer"],
                 expect_ok=False)
    if result.returncode == 0 or "entry 'optimizer' is not a state dict" not in result.stderr:
        fail("--key optimizer: expected an error")
    run([sys.executable, converter, pt, f"{work}/key.safetensors", "--key", "gen"])
    if read_safetensors(f"{work}/key.safetensors")[0].keys() != converted.keys():
        fail("--key gen: different tensors")
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
