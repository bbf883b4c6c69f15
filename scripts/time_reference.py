#!/usr/bin/python3
"""Time the reference SIMPLI generator (SamsungLabs/MLI) with PyTorch on the CPU.

`simpli bench infer --reference DIR` runs this script to put a reference time beside its own,
measured in the same run on the same machine; it can also be run by hand:

    /usr/bin/python3 scripts/time_reference.py --reference ~/src/MLI --size 512x384 --views 8

It needs the user's checkout of the reference sources (never part of simpli) and PyTorch
(Debian: python3-torch, python3-yaml). The reference generator runs in eval mode under
torch.no_grad() with random weights (the time does not depend on their values), on the same
input sizes as simpli's benchmark: V source images of WIDTHxHEIGHT, cameras on a small planar rig,
the config's planes. What it cannot run on a CPU is stubbed, and nothing else:
  * the mesh rasterizer (nvdiffrast, CUDA only) returns black images of the requested size, so the
    MLI correction levels' re-rendering of the sources costs nothing here (simpli's time includes
    its rasterizer: the ratio is in the reference's favour);
  * modules imported only by training code (torchvision, kornia, termcolor) are empty stand-ins.

The last line of output is machine readable: `reference_ms <median> ...`. Exit status 2 means the
reference or PyTorch is missing (the reason is printed), 1 any other failure.
"""

import argparse
import os
import statistics
import sys
import time
import types

# Modules the generator's forward pass never calls, imported at module level by the reference.
TRAINING_ONLY_MODULES = ["torchvision", "torchvision.transforms", "torchvision.transforms.functional",
                         "termcolor", "kornia", "kornia.geometry", "kornia.geometry.transform",
                         "nvdiffrast", "nvdiffrast.torch"]


class _StandIn(types.ModuleType):
    """An importable module whose every attribute is another stand-in (for unused imports)."""

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return _StandIn(self.__name__ + "." + name)

    def __call__(self, *args, **kwargs):
        return _StandIn(self.__name__ + "()")

    def __mro_entries__(self, bases):
        return (object,)


def parse_size(text):
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--size '{text}': expected WIDTHxHEIGHT, e.g. 512x384")
    if width < 16 or height < 16 or width % 16 or height % 16:
        raise argparse.ArgumentTypeError(f"--size '{text}': both sides must be multiples of 16, >= 16")
    return width, height


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--reference", required=True, help="checkout of SamsungLabs/MLI (has lib/ and pretrained/)")
    p.add_argument("--config", default="pretrained/model4_layers/tblock4.yaml",
                   help="generator config, relative to --reference or absolute (default: SIMPLI-4L)")
    p.add_argument("--size", type=parse_size, default=(512, 384), help="WIDTHxHEIGHT (default 512x384)")
    p.add_argument("--views", type=int, default=8, help="source views (default 8)")
    p.add_argument("--repeat", type=int, default=1, help="timed passes after one warm-up (median printed)")
    p.add_argument("--threads", type=int, default=os.cpu_count(), help="PyTorch threads (default: all cores)")
    args = p.parse_args()
    if args.views < 1 or args.views > 64:
        p.error(f"--views {args.views}: expected 1 .. 64")
    if args.repeat < 1:
        p.error(f"--repeat {args.repeat}: expected >= 1")
    if args.threads < 1:
        p.error(f"--threads {args.threads}: expected >= 1")
    return args


def missing(reason):
    print(f"reference not timed: {reason}", file=sys.stderr)
    sys.exit(2)


def import_reference(root):
    if not os.path.isfile(os.path.join(root, "lib", "networks", "generators", "gen_simpli.py")):
        missing(f"'{root}' is not a checkout of SamsungLabs/MLI (no lib/networks/generators/gen_simpli.py)")
    for name in TRAINING_ONLY_MODULES:
        if name not in sys.modules:
            try:
                __import__(name)
            except ImportError:
                module = _StandIn(name)
                module.__path__ = []
                sys.modules[name] = module
    sys.path.insert(0, root)
    from lib.networks.generators import GeneratorSIMPLI
    from lib.modules.cameras import CameraMultiple
    return GeneratorSIMPLI, CameraMultiple


def make_black_renderer(torch):
    class BlackRenderer(torch.nn.Module):
        """Stands in for the nvdiffrast mesh renderer: black images of the requested size."""

        def forward(self, cameras, verts, faces, custom_resolution=None, verts_rgb=None, **kwargs):
            h, w = custom_resolution
            channels = verts_rgb.shape[-1] - 1 if verts_rgb is not None else 3  # RGBA in, RGB out
            return {"images": torch.zeros(verts.shape[0], channels, h, w, dtype=verts.dtype)}

    return BlackRenderer()


def rig_cameras(torch, CameraMultiple, views, width, height):
    """V cameras on a planar rig looking down +z (world -> camera [R | t]), relative intrinsics."""
    ext = torch.zeros(1, 1, views, 3, 4)
    ext[..., :3, :3] = torch.eye(3)
    for v in range(views):
        ext[0, 0, v, 0, 3] = 0.05 * (v % 4) - 0.075
        ext[0, 0, v, 1, 3] = 0.05 * (v // 4) - 0.025
    intr = torch.tensor([[1.2, 0.0, 0.5], [0.0, 1.2 * width / height, 0.5], [0.0, 0.0, 1.0]])
    src = CameraMultiple(ext, intr.expand(1, 1, views, 3, 3), images_sizes=(height, width))
    ref_ext = torch.zeros(1, 1, 1, 3, 4)
    ref_ext[..., :3, :3] = torch.eye(3)
    ref = CameraMultiple(ref_ext, intr.expand(1, 1, 1, 3, 3), images_sizes=(height, width))
    return src, ref


def main():
    args = parse_args()
    try:
        import torch
        import yaml
    except ImportError as e:
        missing(f"{e.name} is not installed (Debian: apt install python3-torch python3-yaml)")
    torch.set_num_threads(args.threads)
    GeneratorSIMPLI, CameraMultiple = import_reference(args.reference)
    config = args.config if os.path.isabs(args.config) else os.path.join(args.reference, args.config)
    with open(config) as f:
        params = yaml.safe_load(f)["models"]["gen"]
    torch.manual_seed(0)
    gen = GeneratorSIMPLI(params).eval()
    gen.renderer = make_black_renderer(torch)
    width, height = args.size
    torch.manual_seed(1)
    images = torch.rand(1, args.views, 3, height, width) * 2 - 1
    src, ref = rig_cameras(torch, CameraMultiple, args.views, width, height)

    times = []
    with torch.no_grad():
        for i in range(args.repeat + 1):  # the first pass warms up allocators and caches
            start = time.perf_counter()
            gen(images, src, ref)  # the outputs are not needed: only the time
            elapsed = (time.perf_counter() - start) * 1000
            if i > 0:
                times.append(elapsed)
            print(f"{'warm-up' if i == 0 else 'pass ' + str(i)}: {elapsed:.0f} ms", flush=True)
    print(f"reference_ms {statistics.median(times):.1f} size {width}x{height} views {args.views} "
          f"threads {torch.get_num_threads()} torch {torch.__version__}")


if __name__ == "__main__":
    main()
