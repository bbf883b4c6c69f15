"""What the weights scripts (layers-4-to-8.py, weights-to-f32.py) share: the `IN OUT [--force]`
command line, checked before anything is read or written so that a mistake never costs a file;
reading simpli weights (safetensors, F32/F64, a network config in the metadata) with named
errors; writing OUT whole or not at all."""
import json
import os
import struct
import sys

import numpy as np

DTYPES = {'F32': '<f4', 'F64': '<f8'}


class Failure:
    """fail(message): exit 1 with 'SCRIPT: message' (no traceback)."""

    def __init__(self, script):
        self.script = script

    def __call__(self, message):
        sys.exit(f"{self.script}: {message}")


def in_out_arguments(argv, fail):
    """(IN, OUT) of `SCRIPT IN OUT [--force]`; refuses OUT when it is a folder, in a missing
    folder, IN itself, or exists without --force."""
    force = '--force' in argv
    args = [a for a in argv if a != '--force']
    if len(args) != 2 or any(a.startswith('-') for a in args):
        fail(f"usage: {fail.script} IN.safetensors OUT.safetensors [--force]")
    src, dst = args
    folder = os.path.dirname(os.path.abspath(dst))
    if os.path.isdir(dst):
        fail(f"{dst}: is a folder; give the output file's name")
    if not os.path.isdir(folder):
        fail(f"{dst}: its folder {folder} does not exist")
    if os.path.exists(dst) and os.path.exists(src) and os.path.samefile(src, dst):
        fail(f"{dst}: is the input weights; refusing to overwrite them")
    if os.path.exists(dst) and not force:
        fail(f"{dst}: already exists (use --force to replace it)")
    return src, dst


def read_weights(path, fail):
    """({name: NumPy array}, metadata, network config) of simpli weights."""
    try:
        with open(path, 'rb') as f:
            data = f.read()
        n = struct.unpack('<Q', data[:8])[0]
        header = json.loads(data[8:8 + n])
        metadata = header.pop('__metadata__')
        config = json.loads(metadata['network_config'])
    except (OSError, ValueError, KeyError, TypeError, struct.error) as e:
        fail(f"{path}: not simpli weights with a network config in their metadata ({e})")
    tensors = {}
    for name, t in header.items():
        try:
            begin, end = t['data_offsets']
            raw = data[8 + n + begin:8 + n + end]
            if len(raw) != end - begin:
                raise ValueError(f"{len(raw)} of {end - begin} bytes")
            tensors[name] = np.frombuffer(raw, dtype=DTYPES[t['dtype']]).reshape(t['shape']).copy()
        except (KeyError, ValueError, TypeError) as error:
            fail(f"{path}: tensor '{name}' ({t.get('dtype')}, shape {t.get('shape')}) is "
                 f"unreadable or not F32/F64 ({error})")
    return tensors, metadata, config


def write_weights(path, tensors, metadata, fail):
    """Writes {name: F32/F64 array} with the metadata to PATH.partial, then renames it into place."""
    header, blobs, offset = {'__metadata__': metadata}, [], 0
    for name in sorted(tensors):
        raw = tensors[name].tobytes()
        header[name] = {'dtype': 'F32' if tensors[name].dtype == np.float32 else 'F64',
                        'shape': list(tensors[name].shape),
                        'data_offsets': [offset, offset + len(raw)]}
        blobs.append(raw)
        offset += len(raw)
    text = json.dumps(header).encode()
    text += b' ' * ((8 - len(text) % 8) % 8)
    partial = path + '.partial'
    try:
        with open(partial, 'wb') as f:
            f.write(struct.pack('<Q', len(text)))
            f.write(text)
            for raw in blobs:
                f.write(raw)
        os.replace(partial, path)
    except OSError as e:
        if os.path.exists(partial):
            os.remove(partial)
        fail(f"{path}: cannot write ({e.strerror})")
