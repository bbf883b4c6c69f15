"""SimpliPlugin in ParaView (pvpython / pvbatch): load, create, update, render, check pixels.

usage: pv_layer_grid.py [--plugin SO] [--png OUT] [--expect-under DIR]
  --plugin        load this plugin file; without it the plugin must already be loaded
                  (PV_PLUGIN_PATH auto-loads it)
  --png           render the layer from the reference camera, save OUT and check its pixels
  --expect-under  SimpliPlugin.so and libvtkSimpliFilters.so must be mapped from under DIR
                  (proves that an installed plugin finds its installed library)
"""
import argparse
import os
import sys

from paraview.simple import (ColorBy, CreateRenderView, LoadPlugin, Render, SaveScreenshot,
                             Show)
import paraview.simple as pvs

parser = argparse.ArgumentParser()
parser.add_argument("--plugin")
parser.add_argument("--png")
parser.add_argument("--expect-under")
args = parser.parse_args()




if args.png:
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pv_support import fail, hold_x_display  # noqa: E402

x_connection = hold_x_display()

if args.plugin:
    LoadPlugin(args.plugin, ns=globals())
if not hasattr(pvs, "SIMPLILayerGrid") and "SIMPLILayerGrid" not in globals():
    fail("SIMPLILayerGrid is not defined: the plugin did not load")
SIMPLILayerGrid = globals().get("SIMPLILayerGrid") or pvs.SIMPLILayerGrid

if args.expect_under:
    root = os.path.realpath(args.expect_under) + os.sep
    with open("/proc/self/maps") as maps:
        mapped = {line.split()[-1] for line in maps if line.rstrip().endswith(".so")
                  or ".so." in line}
    for name in ("SimpliPlugin.so", "libvtkSimpliFilters.so"):
        hits = [os.path.realpath(p) for p in mapped if os.path.basename(p).startswith(name)]
        if not hits:
            fail(f"{name} is not loaded")
        if not all(h.startswith(root) for h in hits):
            fail(f"{name} loaded from {hits}, expected under {root}")

# --- proxy, properties and data ---------------------------------------------------------------
W, H = 8, 8
src = SIMPLILayerGrid()
props = set(src.ListProperties())
expected_props = {"Width", "Height", "Depth", "Fx", "Fy", "Cx", "Cy", "Color"}
if not expected_props <= props:
    fail(f"missing properties {sorted(expected_props - props)} in {sorted(props)}")
hints = src.SMProxy.GetHints()
menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
if menu is None or menu.GetAttribute("category") != "SIMPLI":
    fail("SIMPLI Layer Grid is not in the SIMPLI menu category")
# Depth 2, Fx = Fy = 1, Cx = 0.5, Cy = 0.25: x in [-1, 1], y in [-0.5, 1.5] at z = 2.
src.Width, src.Height = W, H
src.Depth = 2.0
src.Fx, src.Fy, src.Cx, src.Cy = 1.0, 1.0, 0.5, 0.25
COLOR = (0.2, 0.4, 0.8)
src.Color = list(COLOR) + [1.0]
src.UpdatePipeline()

info = src.GetDataInformation()
if info.GetNumberOfPoints() != W * H:
    fail(f"{info.GetNumberOfPoints()} points, expected {W * H}")
if info.GetNumberOfCells() != 2 * (W - 1) * (H - 1):
    fail(f"{info.GetNumberOfCells()} cells, expected {2 * (W - 1) * (H - 1)}")
arrays = sorted(src.PointData.keys())
# The layout of every MLI layer in the module (SIMPLIMLIToVTK.h).
if arrays != ["Alpha", "Color", "Depth", "RGBA", "TCoords"]:
    fail(f"point arrays {arrays}")
bounds = info.GetBounds()
for got, want in zip(bounds, (-1.0, 1.0, -0.5, 1.5, 2.0, 2.0)):
    if abs(got - want) > 1e-6:
        fail(f"bounds {bounds}")
print("proxy OK:", W * H, "points,", arrays, "bounds", bounds)

if not args.png:
    sys.exit(0)

# --- render from the reference camera with a 90 degree view angle -----------------------------
# tan(45 deg) = 1, so a point (x, y, z) lands at x/z, y/z in [-1, 1] of the view: the layer
# covers columns (x/z in [-0.5, 0.5]) 64..192 and, with the OpenCV y axis pointing down the
# screen, image rows from the top (y/z in [-0.25, 0.75]) 96..224 of a 256 x 256 view.
SIZE = 256
view = CreateRenderView()
view.ViewSize = [SIZE, SIZE]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [0.0, 0.0, 0.0]
display = Show(src, view)
ColorBy(display, ("POINTS", "RGBA"))
display.MapScalars = 0  # the uchar RGBA as it is, no lookup table
display.Ambient, display.Diffuse, display.Specular = 1.0, 0.0, 0.0
# paraview.simple resets the camera on a view's first render; render once so that reset is
# spent before the reference camera is set.
Render(view)
view.CameraPosition = [0.0, 0.0, 0.0]
view.CameraFocalPoint = [0.0, 0.0, 1.0]
view.CameraViewUp = [0.0, -1.0, 0.0]
view.CameraViewAngle = 90.0
view.CameraParallelProjection = 0
Render(view)
SaveScreenshot(args.png, view, ImageResolution=[SIZE, SIZE])

from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402

reader = vtkPNGReader()
reader.SetFileName(args.png)
reader.Update()
image = reader.GetOutput()
dims = image.GetDimensions()
if dims[:2] != (SIZE, SIZE):
    fail(f"screenshot is {dims[:2]}, expected {SIZE}x{SIZE}")


def pixel(col, row_from_top):
    # vtkPNGReader puts row 0 at the bottom.
    y = SIZE - 1 - row_from_top
    return tuple(image.GetScalarComponentAsDouble(col, y, 0, c) for c in range(3))


layer = tuple(255.0 * c for c in COLOR)
black = (0.0, 0.0, 0.0)
checks = [
    ("centre", 128, 128, layer),
    ("inside, near the layer's bottom edge", 128, 210, layer),
    ("inside, near the layer's top edge", 128, 105, layer),
    ("inside, near the left edge", 72, 160, layer),
    ("above the layer (y points down)", 128, 60, black),
    ("below the layer", 128, 240, black),
    ("left of the layer", 40, 160, black),
    ("right of the layer", 216, 160, black),
    ("top-left corner", 3, 3, black),
    ("bottom-right corner", 252, 252, black),
]
bad = []
for what, col, row, want in checks:
    got = pixel(col, row)
    if any(abs(g - w) > 2.0 for g, w in zip(got, want)):
        bad.append(f"{what} ({col}, {row} from top): got {got}, expected {want}")
if bad:
    fail("pixel check failed for " + args.png + ":\n  " + "\n  ".join(bad))
print("render OK:", args.png, "centre", pixel(128, 128))
