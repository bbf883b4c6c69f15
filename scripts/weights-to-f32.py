#!/usr/bin/env python3
"""Weights as shipped: every F64 tensor of a safetensors file (e.g. a run's averaged weights,
RUN/checkpoints/step_N/weights_ema.safetensors) cast to F32, the metadata (network config, step)
kept; F32 tensors are copied as they are.
  /usr/bin/python3 scripts/weights-to-f32.py IN.safetensors OUT.safetensors [--force]
OUT must not exist (--force replaces it) and must not be IN; it is written whole or not at all."""
import sys

import numpy as np

from weights_file import Failure, in_out_arguments, read_weights, write_weights

fail = Failure('weights-to-f32.py')
src, dst = in_out_arguments(sys.argv[1:], fail)
tensors, metadata, _ = read_weights(src, fail)
with np.errstate(over='ignore'):  # checked below, with the tensor's name
    cast = {name: values.astype('<f4') for name, values in tensors.items()}
for name, values in cast.items():
    if not np.all(np.isfinite(values)):
        fail(f"{src}: tensor '{name}' has values that are not finite in F32")
write_weights(dst, cast, metadata, fail)
print(f"wrote {dst}: {len(cast)} tensors as F32")
