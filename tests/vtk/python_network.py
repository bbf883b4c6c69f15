"""The network filters from VTK-Python (/usr/bin/python3).

usage: python_network.py SCENE_DIR WORKDIR
vtkSIMPLIBuildMLI on SCENE_DIR (datasets_small/synthetic/scene_00) with the tiny config and
random weights: from the folder and from vtkSIMPLISceneReader (same layers), the layer layout
(RGBA scalars, Depth, camera and stage times in the field data), a bad SourceViews value
(reported, the request fails). vtkSIMPLITrain: 2 steps of the tiny config on small images into
WORKDIR/run (a table row per step, finite losses, a checkpoint).
"""
import math
import os
import shutil
import sys

import numpy as np
import vtkmodules.all  # noqa: F401  (the whole of VTK first, as users do)
from vtkmodules.util.numpy_support import vtk_to_numpy

from simpli import vtkSIMPLIBuildMLI, vtkSIMPLISceneReader, vtkSIMPLITrain

scene_dir, workdir = sys.argv[1], sys.argv[2]
shutil.rmtree(workdir, ignore_errors=True)
os.makedirs(workdir)


def layers(collection):
    out = []
    for i in range(collection.GetNumberOfPartitionedDataSets()):
        pd = collection.GetPartitionedDataSet(i).GetPartition(0)
        point_data = pd.GetPointData()
        out.append({name: vtk_to_numpy(point_data.GetArray(name)).copy()
                    for name in ("RGBA", "Color", "Alpha", "Depth")})
    return out


# --- Build MLI from the folder ------------------------------------------------------------------
build = vtkSIMPLIBuildMLI()
build.SetSceneFileName(scene_dir)
build.SetConfig("tiny")
build.SetRandomSeed(3)
build.SetSourceViews("1,7")
build.SetCorrectionSteps(2)  # of 3: keeps the test short
build.SetDepthRange(vtkSIMPLIBuildMLI.DEPTH_RANGE_SCENE)
build.Update()
mli = build.GetOutputDataObject(0)
assert mli.GetClassName() == "vtkPartitionedDataSetCollection", mli.GetClassName()
assert mli.GetNumberOfPartitionedDataSets() == 4, mli.GetNumberOfPartitionedDataSets()
from_folder = layers(mli)
for k, layer in enumerate(from_folder):
    pd = mli.GetPartitionedDataSet(k).GetPartition(0)
    assert pd.GetClassName() == "vtkPolyData"
    assert pd.GetNumberOfPoints() == 192 * 128, pd.GetNumberOfPoints()
    assert pd.GetPointData().GetScalars().GetName() == "RGBA"
    assert layer["RGBA"].shape == (192 * 128, 4)
    assert np.all(np.isfinite(layer["Depth"])) and layer["Depth"].min() > 0
    # RGBA is the 8-bit form of Color and Alpha (rounded half away from zero, in double),
    # the farthest layer opaque (the rasterizer's rule, filters/SIMPLIMLIToVTK.h).
    straight = np.concatenate([layer["Color"], layer["Alpha"][:, None]], axis=1)
    expected = np.floor(255.0 * straight.astype(np.float64) + 0.5)
    if k == 0:
        expected[:, 3] = 255.0
    assert np.array_equal(layer["RGBA"].astype(np.float64), expected), k
fd = mli.GetFieldData()
assert fd.GetArray("CameraIntrinsics").GetNumberOfComponents() == 4
assert fd.GetArray("CameraImageSize").GetTuple2(0) == (192.0, 128.0)
names = fd.GetAbstractArray("StageNames")
times = vtk_to_numpy(fd.GetArray("StageTimes"))
stage_names = [names.GetValue(i) for i in range(names.GetNumberOfValues())]
assert stage_names[0] == "read_scene" and stage_names[-1] == "meshes", stage_names
assert len(times) == names.GetNumberOfValues() and np.all(times >= 0)
assert list(vtk_to_numpy(fd.GetArray("SourceViews"))) == [1, 7]
assert "level3_decode" in stage_names and "level4_decode" not in stage_names, stage_names
print("stages:", ", ".join(f"{names.GetValue(i)} {times[i]:.0f} ms" for i in range(len(times))))

# --- the same from the scene reader --------------------------------------------------------------
reader = vtkSIMPLISceneReader()
reader.SetFileName(scene_dir)
build.SetInputConnection(reader.GetOutputPort(0))
build.SetSceneFileName("")
build.Update()
from_reader = layers(build.GetOutputDataObject(0))
assert len(from_reader) == len(from_folder)
for a, b in zip(from_folder, from_reader):
    for name in a:
        assert np.array_equal(a[name], b[name]), name
print("Build MLI OK: 4 layers, folder == scene reader input")

# --- a bad view list: the error names the property and the value, the request fails ----------
errors = []


def record(obj, event, message):
    errors.append(message)


record.CallDataType = "string0"
build.AddObserver("ErrorEvent", record)
build.GetExecutive().AddObserver("ErrorEvent", lambda obj, event: None)
build.SetSourceViews("0,99")
assert build.GetExecutive().Update() == 0, "SourceViews 0,99 must fail the request"
assert any("SourceViews '0,99'" in e and "99" in e for e in errors), errors
assert build.GetOutputDataObject(0).GetNumberOfPartitionedDataSets() == 0

# --- Train ----------------------------------------------------------------------------------------
train = vtkSIMPLITrain()
run = os.path.join(workdir, "run")
train.SetDataPath(scene_dir)
train.SetConfig("tiny")
train.SetRunDirectory(run)
train.SetSteps(2)
train.SetSeed(1)
train.SetImageSize(64, 48)
progress = []
train.AddObserver("ProgressEvent", lambda obj, event: progress.append(obj.GetProgress()))
train.Update()
table = train.GetOutput()
assert table.GetNumberOfRows() == 2, table.GetNumberOfRows()
for name in ("step", "l1", "total", "lr", "grad_norm", "step_ms"):
    column = table.GetColumnByName(name)
    assert column is not None, name
    values = [column.GetValue(r) for r in range(2)]
    assert all(math.isfinite(v) for v in values), (name, values)
assert [table.GetColumnByName("step").GetValue(r) for r in range(2)] == [1, 2]
assert 0.5 in progress, progress  # step 1 of 2
assert os.path.isdir(os.path.join(run, "checkpoints", "step_00000002")), os.listdir(run)
print("Train OK:", [round(table.GetColumnByName("total").GetValue(r), 4) for r in range(2)])
