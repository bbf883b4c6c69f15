#!/usr/bin/env python3
"""A 4-layer network's weights (17 planes, e.g. tiny-prior) as an 8-layer one, to start training
SIMPLI-8L from a trained SIMPLI-4L (an experiment: docs/training.md session 21).
  /usr/bin/python3 scripts/layers-4-to-8.py IN.safetensors OUT.safetensors
4 layers: groups of 5 planes at stride 4; 8 layers: groups of 3 at stride 2. Layer k of 8 takes
anchor k // 2 of 4 (+ noise of 1e-3 x their RMS, so the copies can learn apart); the depth
decoder's 5 group logits -> positions 0, 2, 4 of the group. The metadata's network config gets
num_layers 8 and the name NAME-8l."""
import json, os, struct, sys
import numpy as np
def fail(message):
    sys.exit(f"layers-4-to-8.py: {message}")
if len(sys.argv) != 3:
    fail("usage: layers-4-to-8.py IN.safetensors OUT.safetensors")
src, dst = sys.argv[1], sys.argv[2]
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
    s, e = t['data_offsets']
    tensors[k] = np.frombuffer(b[8 + n + s:8 + n + e], dtype=dt[t['dtype']]).reshape(t['shape']).copy()
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
with open(tmp, 'wb') as f:
    f.write(struct.pack('<Q', len(hb))); f.write(hb)
    for r in blobs: f.write(r)
os.replace(tmp, dst)
print('wrote', dst)
