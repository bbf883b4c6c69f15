#!/usr/bin/env python3
"""Convert an official SIMPLI generator checkpoint (.pt) to safetensors for `simpli infer`.

The official code (SamsungLabs/MLI) saves PyTorch checkpoints such as
pretrained/model4_layers/model.gen_00660000.pt. This script loads one on the CPU, takes the
generator's state dict, strips the `module.` prefix that DataParallel / apex leave on every key,
and writes the tensors as float32 safetensors with the reference key names (which are the
names simpli's parameter store uses, spec §5), plus `__metadata__` entries
`config` (official-4l or official-8l, which `simpli infer` resolves to the built-in config) and
`n_parameters`.

Only PyTorch is needed (to unpickle the checkpoint); the safetensors file is written with the
standard library (struct + json). Usage:

    python3 scripts/convert_reference_checkpoint.py model.gen_00660000.pt model/weights/default.safetensors
    simpli infer SCENE --weights model/weights/default.safetensors --out OUT

Options: --config official-4l|official-8l (default: from the number of deformer anchors),
--key NAME (the checkpoint entry holding the state dict, when it is not found automatically).
"""
import argparse
import json
import os
import struct
import sys

# Entries under which training scripts commonly store the generator's state dict.
CANDIDATE_KEYS = ("state_dict", "model", "gen", "generator", "model_state_dict", "net")
ANCHOR_KEY = "planes_deformer_lvl1.anchor"
checkpoint_path = "checkpoint"  # named in every error message


def error(message):
    sys.exit(f"error: {checkpoint_path}: {message}")


def find_state_dict(checkpoint, key):
    """The {name: tensor} mapping inside a loaded checkpoint."""
    import torch

    def is_state_dict(d):
        return isinstance(d, dict) and d and all(torch.is_tensor(v) for v in d.values())

    if key is not None:
        if not isinstance(checkpoint, dict) or key not in checkpoint:
            error(f"the checkpoint has no entry '{key}'")
        checkpoint = checkpoint[key]
        if not is_state_dict(checkpoint):
            error(f"entry '{key}' is not a state dict of tensors")
        return checkpoint
    if is_state_dict(checkpoint):
        return checkpoint
    if isinstance(checkpoint, dict):
        for k in CANDIDATE_KEYS:
            if is_state_dict(checkpoint.get(k)):
                return checkpoint[k]
        error("no state dict found; top-level entries: "
                 + ", ".join(map(str, checkpoint.keys())) + " (choose one with --key)")
    error(f"the checkpoint is a {type(checkpoint).__name__}, not a dict")


def strip_module_prefix(state):
    out = {}
    for name, tensor in state.items():
        plain = name[len("module."):] if name.startswith("module.") else name
        if plain in out:
            error(f"key '{plain}' appears both with and without the 'module.' prefix")
        out[plain] = tensor
    return out


def write_safetensors(path, tensors, metadata):
    """tensors: {name: (shape list, flat list of floats)}, written as little-endian F32."""
    header = {"__metadata__": metadata}
    offset = 0
    for name in sorted(tensors):
        shape, values = tensors[name]
        size = 4 * len(values)
        header[name] = {"dtype": "F32", "shape": list(shape), "data_offsets": [offset, offset + size]}
        offset += size
    text = json.dumps(header, separators=(",", ":")).encode("utf-8")
    text += b" " * (-len(text) % 8)  # the data section starts 8-byte aligned
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(struct.pack("<Q", len(text)))
        f.write(text)
        for name in sorted(tensors):
            values = tensors[name][1]
            f.write(struct.pack("<%df" % len(values), *values))
    os.replace(tmp, path)  # never leaves a partial file at `path`


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("checkpoint", help="official generator checkpoint (.pt)")
    parser.add_argument("output", help="safetensors file to write")
    parser.add_argument("--config", choices=("official-4l", "official-8l"),
                        help="network config (default: from the number of deformer anchors)")
    parser.add_argument("--key", help="checkpoint entry holding the state dict")
    args = parser.parse_args()

    import torch

    global checkpoint_path
    checkpoint_path = args.checkpoint
    try:
        checkpoint = torch.load(args.checkpoint, map_location="cpu")
    except Exception as e:  # missing, truncated, not a torch file: all reported the same way
        error(f"cannot read the checkpoint: {e}")
    state = strip_module_prefix(find_state_dict(checkpoint, args.key))
    if ANCHOR_KEY not in state:
        error(f"'{ANCHOR_KEY}' is missing: not a SIMPLI generator state dict")
    config = args.config or "official-%dl" % state[ANCHOR_KEY].shape[0]
    if config not in ("official-4l", "official-8l"):
        error(f"{state[ANCHOR_KEY].shape[0]} anchors: expected 4 or 8 layers")

    tensors = {}
    for name, t in state.items():
        if not t.is_floating_point():
            error(f"tensor '{name}' has dtype {t.dtype}, expected floating point")
        t = t.detach().to(torch.float32).contiguous()
        tensors[name] = (list(t.shape), t.flatten().tolist())
    count = sum(len(v) for _, v in tensors.values())
    write_safetensors(args.output, tensors, {"config": config, "n_parameters": str(count)})
    print(f"wrote {args.output}: {len(tensors)} tensors, {count} parameters, config {config}")


if __name__ == "__main__":
    main()
