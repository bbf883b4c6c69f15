#!/usr/bin/env python3
"""A 4-layer network's weights (17 planes, e.g. tiny-prior) as an 8-layer one, to start training
SIMPLI-8L from a trained SIMPLI-4L (an experiment: docs/training.md session 21).
  /usr/bin/python3 scripts/layers-4-to-8.py IN.safetensors OUT.safetensors [--force]
OUT must not exist (--force replaces it) and must not be IN; it is written whole or not at all.
4 layers: groups of 5 planes at stride 4; 8 layers: groups of 3 at stride 2. Layer k of 8 takes
anchor k // 2 of 4 (+ noise of 1e-3 x their RMS, so the copies can learn apart); the depth
decoder's 5 group logits -> positions 0, 2, 4 of the group. The metadata's network config gets
num_layers 8 and the name NAME-8l."""
import json, os, struct, sys
import numpy as np
def fail(message):
    sys.exit(f"layers-4-to-8.py: {message}")
args = sys.argv[1:]
force = '--force' in args
args = [a for a in args if a != '--force']
if len(args) != 2 or any(a.startswith('-') for a in args):
    fail("usage: layers-4-to-8.py IN.safetensors OUT.safetensors [--force]")
src, dst = args
# Checked before anything is read or written, so a mistake never costs a file.
if os.path.isdir(dst):
    fail(f"{dst}: is a folder; give the output file's name")
if not os.path.isdir(os.path.dirname(os.path.abspath(dst))):
    fail(f"{dst}: its folder {os.path.dirname(os.path.abspath(dst))} does not exist")
if os.path.exists(dst) and os.path.exists(src) and os.path.samefile(src, dst):
    fail(f"{dst}: is the input weights; refusing to overwrite them")
if os.path.exists(dst) and not force:
    fail(f"{dst}: already exists (use --force to replace it)")
try:
    b = open(src, 'rb').read()
    n = struct.unpack('<Q', b[:8])[0]
    h = json.loads(b[8:8 + n])
    meta = h.pop('__metadata__')
    cfg = json.loads(meta['network_config'])
except (OSError, ValueError, KeyError, struct.error) as e:
    fail(f"{src}: not simpli weights with a network config in their metadata ({e})")
if cfg.get('num_layers') != 4 or cfg.get('num_planes') != 17 or cfg.get('mpi_only'):
    fail(f"{src}: network '{cfg.get('name')}' has num_layers {cfg.get('num_layers')}, num_planes "
         f"{cfg.get('num_planes')}, mpi_only {cfg.get('mpi_only')}; expected 4, 17, false")
dt = {'F32': '<f4', 'F64': '<f8'}
tensors = {}
for k, t in h.items():
    try:
        s, e = t['data_offsets']
        tensors[k] = np.frombuffer(b[8 + n + s:8 + n + e], dtype=dt[t['dtype']]).reshape(t['shape']).copy()
    except (KeyError, ValueError, TypeError) as error:
        fail(f"{src}: tensor '{k}' ({t.get('dtype')}, shape {t.get('shape')}) is unreadable "
             f"or not F32/F64 ({error})")
for k in ('planes_deformer_lvl1.anchor', 'depth_decoder_lvl1.model.2.conv.weight',
          'depth_decoder_lvl1.model.2.conv.bias'):
    if k not in tensors or tensors[k].ndim < 1 or tensors[k].shape[0] != (4 if 'anchor' in k else 5):
        fail(f"{src}: tensor '{k}' is missing or not of a 4-layer network "
             f"(shape {tensors[k].shape if k in tensors else None})")
rng = np.random.default_rng(0)
a = tensors['planes_deformer_lvl1.anchor']
a8 = np.repeat(a, 2, axis=0)
a8 += rng.normal(0, 1e-3 * np.sqrt((a ** 2).mean()), a8.shape).astype(a8.dtype)
tensors['planes_deformer_lvl1.anchor'] = a8
for suffix in ('weight', 'bias'):
    k = 'depth_decoder_lvl1.model.2.conv.' + suffix
    tensors[k] = tensors[k][[0, 2, 4]].copy()
cfg['num_layers'] = 8
cfg['name'] = cfg['name'] + '-8l'
meta['network_config'] = json.dumps(cfg, indent=2)
meta['converted_from'] = src
header, blobs, off = {'__metadata__': meta}, [], 0
for k in sorted(tensors):
    raw = tensors[k].tobytes()
    header[k] = {'dtype': 'F32' if tensors[k].dtype == np.float32 else 'F64', 'shape': list(tensors[k].shape), 'data_offsets': [off, off + len(raw)]}
    blobs.append(raw); off += len(raw)
hb = json.dumps(header).encode()
hb += b' ' * ((8 - len(hb) % 8) % 8)
tmp = dst + '.partial'  # renamed when complete: never a half-written OUT
try:
    with open(tmp, 'wb') as f:
        f.write(struct.pack('<Q', len(hb))); f.write(hb)
        for r in blobs: f.write(r)
    os.replace(tmp, dst)
except OSError as e:
    if os.path.exists(tmp):
        os.remove(tmp)
    fail(f"{dst}: cannot write ({e.strerror})")
print('wrote', dst)
