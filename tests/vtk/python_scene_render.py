"""Scene reader and render view from VTK-Python (/usr/bin/python3).

usage: python_scene_render.py SCENE_DIR WORKDIR
Reads SCENE_DIR (datasets_small/synthetic/scene_00) with vtkSIMPLISceneReader and checks views,
cameras, bounds and frusta; builds a one-layer MLI from view 0's image and ground-truth depth
(scene_mli.py), writes it with vtkMLIWriter, reads it back with vtkMLIReader and renders it
with vtkSIMPLIRenderView: at view 0 (must reproduce the image), at view 6 (a novel view: close
to the photo except at disocclusions), along a spiral (time steps, non-empty frames); then
bad input (reported, the request fails).
"""
import os
import shutil
import sys

import numpy as np
import vtkmodules.all  # noqa: F401  (the whole of VTK first, as users do)
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

from simpli import (vtkMLIReader, vtkMLIWriter, vtkSIMPLIRenderView,  # noqa: E402
                    vtkSIMPLISceneReader)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_mli  # noqa: E402

scene_dir, workdir = sys.argv[1], sys.argv[2]
shutil.rmtree(workdir, ignore_errors=True)
os.makedirs(workdir)

# --- the scene ------------------------------------------------------------------------------------
scene = vtkSIMPLISceneReader()
assert scene.CanReadFile(scene_dir) == 1
scene.SetFileName(scene_dir)
scene.SetFrustumScale(0.3)
scene.Update()
views = scene.GetOutputDataObject(0)
assert views.GetClassName() == "vtkPartitionedDataSetCollection", views.GetClassName()
assert views.GetNumberOfPartitionedDataSets() == 12, views.GetNumberOfPartitionedDataSets()
near, far = views.GetFieldData().GetArray("NearFar").GetTuple2(0)
scale = views.GetFieldData().GetArray("NormalisationScale").GetValue(0)
assert abs(near - 1.0) < 1e-12 and far > near, (near, far)
view0 = views.GetPartitionedDataSet(0).GetPartition(0)
assert view0.GetDimensions() == (192, 128, 1), view0.GetDimensions()
assert view0.GetPointData().GetScalars().GetName() == "RGB"
frustums = scene.GetOutputDataObject(1)
assert frustums.GetNumberOfLines() == 12 and frustums.GetNumberOfPoints() == 60
assert frustums.GetCellData().GetArray("ViewIndex").GetValue(11) == 11
k, E, size = scene_mli.view_camera(view0)
centre = -E[:, :3].T @ E[:, 3]
assert np.allclose(frustums.GetPoint(0), centre), (frustums.GetPoint(0), centre)

# --- an MLI from view 0 ---------------------------------------------------------------------------
name = view0.GetFieldData().GetAbstractArray("ViewName").GetValue(0)
name = name if name.endswith(".png") else name + ".png"
depth = scene_mli.read_depth(scene_dir, name, scale)
assert 0.9 < depth.min() < depth.max() < far * 1.01, (depth.min(), depth.max(), far)
mli_dir = os.path.join(workdir, "view0_mli")
writer = vtkMLIWriter()
writer.SetInputData(scene_mli.mli_collection(view0, depth))
writer.SetFileName(mli_dir)
writer.SetFormatToLossless()
assert writer.Write() == 1
mli = vtkMLIReader()
mli.SetFileName(mli_dir)

# --- render at view 0: the image comes back ------------------------------------------------------
render = vtkSIMPLIRenderView()
render.SetInputConnection(0, mli.GetOutputPort())
render.SetSceneConnection(scene.GetOutputPort(0))
render.SetCameraMode(vtkSIMPLIRenderView.CAMERA_SCENE_VIEW)
render.SetViewIndex(0)
render.Update()
out = render.GetOutput()
assert out.GetDimensions() == (192, 128, 1), out.GetDimensions()
rgb = vtk_to_numpy(out.GetPointData().GetArray("RGB")).reshape(128, 192, 3)[::-1]
truth = scene_mli.view_rgb(view0)
p0 = scene_mli.psnr(scene_mli.crop(rgb), scene_mli.crop(truth))
assert p0 > 40.0, p0
d = vtk_to_numpy(out.GetPointData().GetArray("Depth")).reshape(128, 192)[::-1]
assert np.abs(scene_mli.crop(d) - scene_mli.crop(depth.astype(np.float32))).max() < 1e-3

# --- a novel view: close to its photo -------------------------------------------------------------
render.SetViewIndex(6)
render.Update()
rgb6 = vtk_to_numpy(render.GetOutput().GetPointData().GetArray("RGB")).reshape(128, 192, 3)[::-1]
truth6 = scene_mli.view_rgb(views.GetPartitionedDataSet(6).GetPartition(0))
p6 = scene_mli.psnr(scene_mli.crop(rgb6), scene_mli.crop(truth6))
assert p6 > 25.0, p6  # 30.5 dB measured: only disocclusions differ

# --- spiral: time steps and frames ----------------------------------------------------------------
render.SetCameraMode(vtkSIMPLIRenderView.CAMERA_TRAJECTORY)
render.SetNumberOfFrames(10)
render.SetWidth(96)
render.UpdateInformation()
steps = render.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
assert list(steps) == list(range(10)), steps
render.UpdateTimeStep(4)
frame = render.GetOutput()
assert frame.GetDimensions() == (96, 64, 1), frame.GetDimensions()
assert frame.GetFieldData().GetArray("FrameIndex").GetValue(0) == 4
opacity = vtk_to_numpy(frame.GetPointData().GetArray("Opacity"))
assert (opacity > 0.99).mean() > 0.8, (opacity > 0.99).mean()

# --- bad input ------------------------------------------------------------------------------------
errors = []


def record(obj, event, message):
    errors.append(message)


record.CallDataType = "string0"
bad = vtkSIMPLISceneReader()
bad.AddObserver("ErrorEvent", record)
bad.GetExecutive().AddObserver("ErrorEvent", lambda o, e: None)  # mute the executive's echo
bad.SetFileName(os.path.join(workdir, "no_such_scene"))
assert bad.GetExecutive().Update() == 0
assert any("no_such_scene" in e and "does not exist" in e for e in errors), errors
render.SetCameraMode(vtkSIMPLIRenderView.CAMERA_SCENE_VIEW)
render.SetViewIndex(99)
render.AddObserver("ErrorEvent", record)
render.GetExecutive().AddObserver("ErrorEvent", lambda o, e: None)
assert render.GetExecutive().Update() == 0
assert any("ViewIndex 99 is out of range" in e for e in errors), errors

print(f"scene python OK: PSNR view 0 {p0:.2f} dB (the MLI's own view), view 6 {p6:.2f} dB")
