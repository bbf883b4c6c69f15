"""The scene reader and render view proxies of SimpliPlugin in pvpython / pvbatch.

usage: pv_scene_render.py --plugin SO --scene DIR --workdir DIR
Loads the plugin; reads DIR (datasets_small/synthetic/scene_00) with SIMPLISceneReader (views
and frusta, properties, menu, file picker hint); builds a one-layer MLI from view 0's image and
ground-truth depth (scene_mli.py, through the `simpli` package on PYTHONPATH) and writes it;
reads it with SIMPLIMLIReader; renders it with SIMPLIRenderView at view 0 (must give the
image back), with the same camera given explicitly (same pixels), and along a trajectory (time
steps reach the animation's time keeper, a time selects the frame); then shows the rendered
image (slice, MapScalars off) and the MLI itself from view 0's camera (converted to view angle /
position / focal point / view up, MapScalars off) in render views, saves screenshots and
checks their pixels against the photo. Renders, so it needs an X server (xvfb-run).
"""
import argparse
import os
import shutil
import sys

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--scene", required=True)
parser.add_argument("--workdir", required=True)
args = parser.parse_args()




sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pv_support import fail, hold_x_display, read_png_rgb, screenshot_from_camera  # noqa: E402

x_connection = hold_x_display()

import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

from simpli import vtkMLIWriter  # noqa: E402

from paraview.simple import (ColorBy, CreateRenderView, GetAnimationScene,  # noqa: E402
                             GetTimeKeeper, LoadPlugin, OpenDataFile, OutputPort, Render,
                             SaveScreenshot, Show)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_mli  # noqa: E402

shutil.rmtree(args.workdir, ignore_errors=True)
os.makedirs(args.workdir)

LoadPlugin(args.plugin, ns=globals())
for name in ("SIMPLISceneReader", "SIMPLIRenderView", "SIMPLIMLIReader"):
    if name not in globals():
        fail(f"{name} is not defined: the plugin did not load")

# --- scene reader ------------------------------------------------------------------------------
scene = SIMPLISceneReader(FileName=args.scene)  # noqa: F821  (defined by LoadPlugin)
props = set(scene.ListProperties())
expected = {"FileName", "FrustumScale", "Normalise", "SizeMultiple", "ImagesDirectory"}
if not expected <= props:
    fail(f"scene reader lacks properties {sorted(expected - props)}")
hints = scene.SMProxy.GetHints()
menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
if menu is None or menu.GetAttribute("category") != "SIMPLI":
    fail("SIMPLI Scene Reader is not in the SIMPLI menu")
file_hints = scene.SMProxy.GetProperty("FileName").GetHints()
if file_hints is None or file_hints.FindNestedElementByName("UseDirectoryName") is None:
    fail("FileName has no UseDirectoryName hint (the file dialog would not pick folders)")
scene.UpdatePipeline()
if scene.SMProxy.GetNumberOfOutputPorts() != 2:
    fail(f"{scene.SMProxy.GetNumberOfOutputPorts()} output ports, expected 2")
views_info = scene.GetDataInformation(0)
if views_info.GetNumberOfPoints() != 12 * 192 * 128:
    fail(f"views: {views_info.GetNumberOfPoints()} points")
frustum_info = scene.GetDataInformation(1)
if frustum_info.GetNumberOfCells() != 12 or frustum_info.GetNumberOfPoints() != 60:
    fail(f"frusta: {frustum_info.GetNumberOfCells()} cells, {frustum_info.GetNumberOfPoints()} points")
views = scene.GetClientSideObject().GetOutputDataObject(0)
view0 = views.GetPartitionedDataSet(0).GetPartition(0)
scale = views.GetFieldData().GetArray("NormalisationScale").GetValue(0)
# File > Open on poses_bounds.npy picks the scene reader (ReaderFactory hint, CanReadFile).
opened = OpenDataFile(os.path.join(args.scene, "poses_bounds.npy"))
if opened is None or opened.GetXMLName() != "SIMPLISceneReader":
    fail(f"OpenDataFile(poses_bounds.npy) gave {opened and opened.GetXMLName()}")
opened.UpdatePipeline()
if opened.GetDataInformation(0).GetNumberOfPoints() != 12 * 192 * 128:
    fail("poses_bounds.npy opened, but the views differ")
print("scene reader OK:", views.GetNumberOfPartitionedDataSets(), "views")

# --- an MLI from view 0, written with the simpli package, read by the proxy ---------------------
name = view0.GetFieldData().GetAbstractArray("ViewName").GetValue(0)
name = name if name.endswith(".png") else name + ".png"
depth = scene_mli.read_depth(args.scene, name, scale)
mli_dir = os.path.join(args.workdir, "view0_mli")
writer = vtkMLIWriter()
writer.SetInputData(scene_mli.mli_collection(view0, depth))
writer.SetFileName(mli_dir)
writer.SetFormatToLossless()
if writer.Write() != 1:
    fail("writing the MLI failed")
mli = SIMPLIMLIReader(FileName=mli_dir)  # noqa: F821

# --- render view proxy -------------------------------------------------------------------------------
render = SIMPLIRenderView(Input=mli, Scene=OutputPort(scene, 0))  # noqa: F821
expected = {"Input", "Scene", "CameraMode", "ViewIndex", "Intrinsics", "Extrinsics", "ImageSize",
            "TrajectoryType", "NumberOfFrames", "FrameIndex", "TrajectoryRadii", "FocusDepth",
            "Width", "Height", "Interpolation", "MaxFragments"}
if not expected <= set(render.ListProperties()):
    fail(f"render view lacks {sorted(expected - set(render.ListProperties()))}")
render.CameraMode = "Scene View"
render.ViewIndex = 0
render.Interpolation = "Perspective Correct"
render.UpdatePipeline()
out = render.GetClientSideObject().GetOutputDataObject(0)
if out.GetDimensions() != (192, 128, 1):
    fail(f"render view output {out.GetDimensions()}")
rgb = vtk_to_numpy(out.GetPointData().GetArray("RGB")).reshape(128, 192, 3)[::-1]
truth = scene_mli.view_rgb(view0)
p0 = scene_mli.psnr(scene_mli.crop(rgb), scene_mli.crop(truth))
if p0 < 40.0:
    fail(f"render at view 0: PSNR {p0:.2f} dB against the photo, expected > 40")
print(f"render view OK: view 0 PSNR {p0:.2f} dB")

# The same camera given explicitly (the Intrinsics / Extrinsics / ImageSize properties).
(fx, fy, cx, cy), E, (W, H) = scene_mli.view_camera(view0)
render.CameraMode = "Explicit"
render.Intrinsics = [fx, fy, cx, cy]
render.Extrinsics = [float(v) for v in E.reshape(-1)]
render.ImageSize = [W, H]
render.UpdatePipeline()
explicit = render.GetClientSideObject().GetOutputDataObject(0)
rgb_explicit = vtk_to_numpy(explicit.GetPointData().GetArray("RGB")).reshape(128, 192, 3)[::-1]
if not np.array_equal(rgb_explicit, rgb):
    fail("the explicit camera (view 0's) renders differently from Scene View 0")
print("explicit camera OK")

render.CameraMode = "Trajectory"
render.TrajectoryType = "Orbit"
render.NumberOfFrames = 8
render.UpdatePipelineInformation()
steps = list(render.TimestepValues)
if steps != [float(i) for i in range(8)]:
    fail(f"TimestepValues {steps}")
GetAnimationScene().UpdateAnimationUsingDataTimeSteps()
if len(GetTimeKeeper().TimestepValues) != 8:
    fail(f"time keeper has {len(GetTimeKeeper().TimestepValues)} time steps")
render.UpdatePipeline(time=3.0)
frame = render.GetClientSideObject().GetOutputDataObject(0)
if frame.GetFieldData().GetArray("FrameIndex").GetValue(0) != 3:
    fail(f"time 3 rendered frame {frame.GetFieldData().GetArray('FrameIndex').GetValue(0)}")
print("trajectory OK: 8 time steps, time 3 -> frame 3")

# --- OpenGL render of the MLI from view 0's camera, MapScalars off ----------------------------------
png = os.path.join(args.workdir, "view0.png")
shot = screenshot_from_camera(mli, E, fy, W, H, png)[::-1]
p_gl = scene_mli.psnr(scene_mli.crop(shot), scene_mli.crop(truth))
# Pixel check: nearly every pixel of the central crop matches the photo (OpenGL samples the
# same vertices; only pixels at depth edges, where the 8-bit RGBA and the rasterisation rules
# differ, may stray), and the centre pixel does.
diff = np.abs(scene_mli.crop(shot).astype(int) - scene_mli.crop(truth).astype(int)).max(axis=-1)
close = float((diff <= 8).mean())
centre = np.abs(shot[64, 96].astype(int) - truth[64, 96].astype(int)).max()
if p_gl < 35.0 or close < 0.95 or centre > 4:
    fail(f"screenshot {png}: PSNR {p_gl:.2f} dB against the photo, {100 * close:.1f} % of the "
         f"pixels within 8 levels, centre pixel {shot[64, 96]} vs {truth[64, 96]}")

# --- the rendered image itself in a render view (slice of the image data, RGB direct) -----------
render.CameraMode = "Scene View"
render.ViewIndex = 0
image_view = CreateRenderView()
image_view.ViewSize = [W, H]
image_view.OrientationAxesVisibility = 0
image_view.UseColorPaletteForBackground = 0
image_view.Background = [0.0, 0.0, 0.0]
image_display = Show(render, image_view)
image_display.SetRepresentationType("Slice")
ColorBy(image_display, ("POINTS", "RGB"))
image_display.MapScalars = 0
Render(image_view)
# Look straight at the W x H image (point spacing 1): its extent exactly fills the window.
image_view.InteractionMode = "2D"
image_view.CameraPosition = [(W - 1) / 2.0, (H - 1) / 2.0, 1000.0]
image_view.CameraFocalPoint = [(W - 1) / 2.0, (H - 1) / 2.0, 0.0]
image_view.CameraViewUp = [0.0, 1.0, 0.0]
image_view.CameraParallelProjection = 1
image_view.CameraParallelScale = H / 2.0
Render(image_view)
png_image = os.path.join(args.workdir, "render_view_image.png")
SaveScreenshot(png_image, image_view, ImageResolution=[W, H])
shown = read_png_rgb(png_image, W, H)[::-1]
p_img = scene_mli.psnr(scene_mli.crop(shown), scene_mli.crop(truth))
if p_img < 35.0:
    fail(f"the render view's image shown in ParaView ({png_image}): PSNR {p_img:.2f} dB")
print(f"render view image shown OK: {png_image}, PSNR {p_img:.2f} dB against the photo")
print(f"screenshot OK: {png}, PSNR {p_gl:.2f} dB against the photo, "
      f"{100 * close:.1f} % of the pixels within 8 levels")
