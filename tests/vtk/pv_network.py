"""The network proxies of SimpliPlugin in pvpython.

usage: pv_network.py --plugin SO --scene DIR --workdir DIR
Loads the plugin; SIMPLISceneReader(DIR) -> SIMPLIBuildMLI (tiny config, random weights:
no trained weights are needed) -> shown in a render view from the MLI's reference camera with
MapScalars = 0 (the layers' RGBA directly), screenshot checked: the layers cover the view,
and it matches the layers' RGBA composited back to front (PSNR). Also checks the proxies'
properties, menu category, file-chooser hints, the Depth Range enumeration,
SIMPLIRenderView on the built MLI, and one SIMPLITrain step into DIR/run. Renders, so it
needs an X server (xvfb-run).
"""
import argparse
import math
import os
import shutil
import sys

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--scene", required=True)
parser.add_argument("--workdir", required=True)
args = parser.parse_args()




sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pv_support import fail, hold_x_display, screenshot_from_camera  # noqa: E402

x_connection = hold_x_display()

import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

from paraview.simple import LoadPlugin, OutputPort, SetActiveSource  # noqa: E402

shutil.rmtree(args.workdir, ignore_errors=True)
os.makedirs(args.workdir)

LoadPlugin(args.plugin, ns=globals())
for name in ("SIMPLISceneReader", "SIMPLIBuildMLI", "SIMPLITrain", "SIMPLIRenderView"):
    if name not in globals():
        fail(f"{name} is not defined: the plugin did not load")


def in_simpli_menu(proxy):
    hints = proxy.SMProxy.GetHints()
    menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
    return menu is not None and menu.GetAttribute("category") == "SIMPLI"


# --- Build MLI proxy ------------------------------------------------------------------------------
scene = SIMPLISceneReader(FileName=args.scene)  # noqa: F821  (defined by LoadPlugin)
build = SIMPLIBuildMLI(Input=OutputPort(scene, 0))  # noqa: F821
expected = {"Input", "SceneFileName", "WeightsFile", "Config", "SourceViews", "DropEmptyLayers",
            "EmptyLayerThreshold", "DropTransparentTriangles", "DepthRange", "CorrectionSteps",
            "NumberOfPlanes", "InputScale", "ReferenceMargin", "Device", "RandomSeed"}
if not expected <= set(build.ListProperties()):
    fail(f"Build MLI lacks {sorted(expected - set(build.ListProperties()))}")
if not in_simpli_menu(build):
    fail("SIMPLI Build MLI is not in the SIMPLI menu")
for prop, hint in (("WeightsFile", "FileChooser"), ("SceneFileName", "UseDirectoryName")):
    hints = build.SMProxy.GetProperty(prop).GetHints()
    if hints is None or hints.FindNestedElementByName(hint) is None:
        fail(f"{prop} has no {hint} hint")
if list(build.GetProperty("DepthRange").Available) != ["Config", "Scene"]:
    fail(f"DepthRange entries {list(build.GetProperty('DepthRange').Available)}")
build.Config = "tiny"
build.RandomSeed = 3
build.SourceViews = "0,4,8"
build.DepthRange = "Scene"
build.UpdatePipeline()
info = build.GetDataInformation()
if info.GetNumberOfPoints() != 4 * 192 * 128:
    fail(f"Build MLI: {info.GetNumberOfPoints()} points, expected 4 layers of 192 x 128")
mli = build.GetClientSideObject().GetOutputDataObject(0)
fd = mli.GetFieldData()
E = np.array(fd.GetArray("CameraExtrinsics").GetTuple(0)).reshape(3, 4)
fx, fy, cx, cy = fd.GetArray("CameraIntrinsics").GetTuple(0)
W, H = (int(v) for v in fd.GetArray("CameraImageSize").GetTuple(0))
print("Build MLI OK:", mli.GetNumberOfPartitionedDataSets(), "layers",
      [fd.GetAbstractArray("StageNames").GetValue(i)
       for i in range(fd.GetAbstractArray("StageNames").GetNumberOfValues())])

# Without an input (no active source to attach to) the proxy reads Scene File Name itself.
SetActiveSource(None)
from_folder = SIMPLIBuildMLI(SceneFileName=args.scene, Config="tiny", RandomSeed=3,  # noqa: F821
                             SourceViews="0,4,8", DepthRange="Scene", CorrectionSteps=0)
if from_folder.Input is not None and len(from_folder.Input) > 0:
    fail("Build MLI without an input got one")
from_folder.UpdatePipeline()
if from_folder.GetDataInformation().GetNumberOfPoints() != 4 * 96 * 64:
    fail(f"Build MLI from the folder: {from_folder.GetDataInformation().GetNumberOfPoints()} "
         "points, expected 4 layers of 96 x 64 (no corrections: the level-1 resolution)")
print("Build MLI from Scene File Name OK")
# Input Scale 0.5: the sources (and so the MLI) at 96 x 64, with every correction.
from_folder.CorrectionSteps = -1
from_folder.InputScale = 0.5
from_folder.UpdatePipeline()
if from_folder.GetDataInformation().GetNumberOfPoints() != 4 * 96 * 64:
    fail(f"Build MLI at Input Scale 0.5: {from_folder.GetDataInformation().GetNumberOfPoints()} "
         "points, expected 4 layers of 96 x 64")
print("Build MLI at Input Scale 0.5 OK")
# Reference Margin: 0.06 by default; 0.25 is the same texel grid on a frame 1.5 times as wide as
# at 0 (fx / 1.5).
default_margin = from_folder.GetProperty("ReferenceMargin").GetData()
default_margin = default_margin[0] if hasattr(default_margin, "__len__") else default_margin
if abs(default_margin - 0.06) > 1e-12:
    fail(f"Reference Margin defaults to {default_margin}, expected 0.06")
from_folder.ReferenceMargin = 0
from_folder.UpdatePipeline()
narrow_fx = from_folder.GetClientSideObject().GetOutputDataObject(0).GetFieldData().GetArray(
    "CameraIntrinsics").GetTuple(0)[0]
from_folder.ReferenceMargin = 0.25
from_folder.UpdatePipeline()
wide = from_folder.GetClientSideObject().GetOutputDataObject(0).GetFieldData()
if from_folder.GetDataInformation().GetNumberOfPoints() != 4 * 96 * 64:
    fail("Build MLI at Reference Margin 0.25 changed the texel grid")
if abs(wide.GetArray("CameraIntrinsics").GetTuple(0)[0] * 1.5 - narrow_fx) > 1e-9 * narrow_fx:
    fail(f"Reference Margin 0.25: fx {wide.GetArray('CameraIntrinsics').GetTuple(0)[0]}, "
         f"expected {narrow_fx} / 1.5")
from_folder.ReferenceMargin = 0.06
print("Build MLI at Reference Margin 0.25 OK")

# --- the layers in a render view, RGBA directly (MapScalars off) ------------------------------
png = os.path.join(args.workdir, "build_mli.png")
shot = screenshot_from_camera(build, E, fy, W, H, png)
covered = float((shot.astype(int).max(axis=-1) > 8).mean())
if covered < 0.5:
    fail(f"screenshot {png}: only {100 * covered:.1f} % of the pixels differ from the background")
# The layers' own colours, composited back to front over the black background per texel: from
# the reference camera every layer covers the view, texel (i, j) near pixel (i, j). With
# MapScalars off OpenGL shows exactly these colours (a colour map would not).
composite = np.zeros((H, W, 3))
for k in range(mli.GetNumberOfPartitionedDataSets()):
    rgba = vtk_to_numpy(mli.GetPartitionedDataSet(k).GetPartition(0).GetPointData()
                        .GetArray("RGBA")).reshape(H, W, 4).astype(float)[::-1]  # row 0 = bottom
    alpha = rgba[:, :, 3:] / 255.0
    composite = alpha * rgba[:, :, :3] + (1 - alpha) * composite
mean_error = np.abs(shot.reshape(-1, 3).mean(axis=0) - composite.reshape(-1, 3).mean(axis=0)).max()
centre = (slice(H // 8, H - H // 8), slice(W // 8, W - W // 8))
mse = float(((shot[centre].astype(float) - composite[centre]) ** 2).mean())
psnr = 10 * math.log10(255.0 ** 2 / max(mse, 1e-12))
# (51.9 dB here; a flipped image scores 35 dB and a flat image of the mean colour 37 dB.)
if mean_error > 2.0 or psnr < 42.0:
    fail(f"screenshot {png} vs the layers' RGBA composited: mean colour off by "
         f"{mean_error:.2f} levels, PSNR {psnr:.1f} dB (expected <= 2 and >= 42)")
print(f"composite OK: mean colour off by {mean_error:.2f} levels, PSNR {psnr:.1f} dB")
print(f"render OK: {png}, {100 * covered:.1f} % of the pixels show the layers")

# --- the built MLI through SIMPLIRenderView (OpenCL rasterizer) --------------------------------
render = SIMPLIRenderView(Input=build)  # noqa: F821
render.UpdatePipeline()
image = render.GetClientSideObject().GetOutputDataObject(0)
if image.GetDimensions() != (W, H, 1):
    fail(f"render view of the built MLI: {image.GetDimensions()}")
opacity = vtk_to_numpy(image.GetPointData().GetArray("Opacity"))
if opacity.mean() < 0.5:
    fail(f"render view of the built MLI: mean opacity {opacity.mean():.3f}")
# (No pixel comparison with the OpenGL screenshot: the rasterizer makes the farthest layer
# opaque, as the reference renders, while OpenGL blends every layer over the background.)
print(f"SIMPLIRenderView OK: mean opacity {opacity.mean():.3f}")

# --- Train proxy ----------------------------------------------------------------------------------
run = os.path.join(args.workdir, "run")
train = SIMPLITrain(DataPath=args.scene, Config="tiny", RunDirectory=run, Steps=1,  # noqa: F821
                    Seed=2, ImageSize=[64, 48])
expected = {"DataPath", "Config", "RunDirectory", "Steps", "CheckpointEvery", "Resume",
            "VGGWeightsFile", "Seed", "ImageSize", "Device"}
if not expected <= set(train.ListProperties()):
    fail(f"Train lacks {sorted(expected - set(train.ListProperties()))}")
if not in_simpli_menu(train):
    fail("SIMPLI Train is not in the SIMPLI menu")
train.UpdatePipeline()
table = train.GetClientSideObject().GetOutputDataObject(0)
if table.GetNumberOfRows() != 1 or not math.isfinite(table.GetColumnByName("total").GetValue(0)):
    fail(f"Train: {table.GetNumberOfRows()} rows")
if not os.path.isdir(os.path.join(run, "checkpoints", "step_00000001")):
    fail(f"Train: no checkpoint in {run}")
print("Train OK: loss", table.GetColumnByName("total").GetValue(0))
