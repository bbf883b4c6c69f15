#!/usr/bin/python3
"""A photo folder for `"synthetic": {"photo_dir": DIR}` that adds high-frequency texture photos
to the default wallpapers (experiment of docs/training.md, session 17; not the default).

    apt-get install gimp-data            # GIMP's patterns (GPL-3+, /usr/share/gimp/2.0/patterns)
    /usr/bin/python3 scripts/make-texture-mix.py OUT_DIR

OUT_DIR gets a symbolic link to each default photo (the list in model/src/synthetic/photos.cpp)
and every natural GIMP pattern (not Legacy/, starfield, electric, lightning) tiled to >= 384 px
as PNG. Why: the default photos are smooth wallpapers (mean |Laplacian| 0.015-0.024 at the world
scenes' texture scale), real foliage is not (LLFF flower 0.11 at 256x192); the patterns (bark,
stone, burlap, leaves, ...) carry 0.05-0.4. World scenes drawn from the mix: 0.055 (default 0.026).
Needs numpy and PIL (Debian: python3-numpy python3-pil).
"""
import glob
import os
import re
import struct
import sys

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PATTERNS = '/usr/share/gimp/2.0/patterns'
SKIP = {'Legacy', 'starfield.pat', 'electric.pat', 'lightning.pat'}


def read_pattern(path):
    """GIMP .pat: big-endian header (size, version, width, height, bytes per pixel, 'GPAT', name)."""
    data = open(path, 'rb').read()
    header, _, width, height, depth = struct.unpack('>5I', data[:20])
    if data[20:24] != b'GPAT' or depth not in (1, 2, 3, 4):
        raise ValueError(f'{path}: not a GIMP pattern (magic {data[20:24]!r}, {depth} bytes/pixel)')
    pixels = np.frombuffer(data[header:header + width * height * depth], np.uint8)
    pixels = pixels.reshape(height, width, depth)
    if depth <= 2:
        pixels = np.repeat(pixels[..., :1], 3, -1)
    return pixels[..., :3]


def main(out):
    if not os.path.isdir(PATTERNS):
        sys.exit(f'make-texture-mix.py: {PATTERNS} is missing: apt-get install gimp-data')
    os.makedirs(out, exist_ok=True)
    source = open(os.path.join(ROOT, 'model/src/synthetic/photos.cpp')).read()
    walls = [p for p in re.findall(r'"(/usr/share/[^"]+\.(?:jpg|png|jpeg))"', source) if os.path.exists(p)]
    for i, path in enumerate(walls):
        link = os.path.join(out, 'wall_%02d_%s' % (i, os.path.basename(path)))
        if not os.path.lexists(link):
            os.symlink(path, link)
    patterns = 0
    for path in sorted(glob.glob(os.path.join(PATTERNS, '*', '*.pat'))):
        if path.split('/')[-2] in SKIP or os.path.basename(path) in SKIP:
            continue
        tile = read_pattern(path)
        reps = max(1, int(np.ceil(384 / max(tile.shape[:2]))))
        Image.fromarray(np.tile(tile, (reps, reps, 1))).save(
            os.path.join(out, 'tex_' + os.path.basename(path)[:-4] + '.png'))
        patterns += 1
    print(f'{out}: {len(walls)} wallpapers, {patterns} texture patterns')


if __name__ == '__main__':
    if len(sys.argv) != 2:
        sys.exit('usage: make-texture-mix.py OUT_DIR')
    main(sys.argv[1])
