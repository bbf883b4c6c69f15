#!/usr/bin/env python3
"""A 4-layer network's weights (17 planes, e.g. tiny-prior) as an 8-layer one, to start training
SIMPLI-8L from a trained SIMPLI-4L (an experiment: docs/training.md session 21).
  /usr/bin/python3 scripts/layers-4-to-8.py IN.safetensors OUT.safetensors [--force]
OUT must not exist (--force replaces it) and must not be IN; it is written whole or not at all.
4 layers: groups of 5 planes at stride 4; 8 layers: groups of 3 at stride 2. Layer k of 8 takes
anchor k // 2 of 4 (+ noise of 1e-3 x their RMS, so the copies can learn apart); the depth
decoder's 5 group logits -> positions 0, 2, 4 of the group. The metadata's network config gets
num_layers 8 and the name NAME-8l."""
import json
import sys

import numpy as np

from weights_file import Failure, in_out_arguments, read_weights, write_weights

fail = Failure('layers-4-to-8.py')
src, dst = in_out_arguments(sys.argv[1:], fail)
tensors, meta, cfg = read_weights(src, fail)
if cfg.get('num_layers') != 4 or cfg.get('num_planes') != 17 or cfg.get('mpi_only'):
    fail(f"{src}: network '{cfg.get('name')}' has num_layers {cfg.get('num_layers')}, num_planes "
         f"{cfg.get('num_planes')}, mpi_only {cfg.get('mpi_only')}; expected 4, 17, false")
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
write_weights(dst, tensors, meta, fail)
print('wrote', dst)
