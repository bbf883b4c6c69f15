"""MLI reader/writer and image quality from VTK-Python (/usr/bin/python3).

usage: python_mli.py WORKDIR
Builds a two-layer MLI collection by hand in the documented layout, writes it with
vtkMLIWriter (lossless and JPEG), reads it back with vtkMLIReader and checks layers, points,
RGBA, exact floats and the field-data camera; then a bad folder (error reported, request
fails) and vtkSIMPLIImageQuality against numpy.
"""
import math
import os
import shutil
import sys

import numpy as np
import vtkmodules.all  # noqa: F401  (the whole of VTK first, as users do)
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkFloatArray, vtkIntArray
from vtkmodules.vtkCommonDataModel import (vtkCompositeDataSet, vtkImageData,
                                           vtkPartitionedDataSetCollection, vtkPolyData)
from vtkmodules.vtkCommonCore import vtkPoints

from simpli import vtkMLIReader, vtkMLIWriter, vtkSIMPLIImageQuality

workdir = sys.argv[1]
shutil.rmtree(workdir, ignore_errors=True)
os.makedirs(workdir)

W, H, L = 6, 4, 2
rng = np.random.default_rng(7)
# Camera: a rotation about y by 0.3 rad, a translation, off-centre principal point.
c, s = math.cos(0.3), math.sin(0.3)
R = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
t = np.array([0.25, -0.5, 1.5])
fx, fy, cx, cy = 0.9, 1.2, 0.48, 0.4167
depths = [rng.uniform(8.0, 10.0, (H, W)).astype(np.float32),
          rng.uniform(2.0, 3.0, (H, W)).astype(np.float32)]
colors = [rng.uniform(0.0, 1.0, (H, W, 3)).astype(np.float32) for _ in range(L)]
alphas = [rng.uniform(0.0, 1.0, (H, W)).astype(np.float32) for _ in range(L)]


def world_points(depth):
    """Corner-grid back-projection: Xc = d ((u - cx)/fx, (v - cy)/fy, 1), Xw = R^T (Xc - t)."""
    v, u = np.meshgrid(np.arange(H) / (H - 1), np.arange(W) / (W - 1), indexing="ij")
    d = depth.astype(np.float64)
    xc = np.stack([d * (u - cx) / fx, d * (v - cy) / fy, d], axis=-1).reshape(-1, 3)
    return (xc - t) @ R  # rows: R^T (x - t)


def named(array, name):
    array.SetName(name)
    return array


# --- a collection in the documented layout, built by hand --------------------------------------
collection = vtkPartitionedDataSetCollection()
for k in range(L):
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(world_points(depths[k]), deep=1))
    pd.SetPoints(pts)
    pdata = pd.GetPointData()
    pdata.AddArray(named(numpy_to_vtk(colors[k].reshape(-1, 3), deep=1), "Color"))
    pdata.AddArray(named(numpy_to_vtk(alphas[k].reshape(-1), deep=1), "Alpha"))
    pdata.AddArray(named(numpy_to_vtk(depths[k].reshape(-1), deep=1), "Depth"))
    collection.SetPartition(k, 0, pd)
fd = collection.GetFieldData()
intr = vtkDoubleArray()
intr.SetName("CameraIntrinsics")
intr.SetNumberOfComponents(4)
intr.InsertNextTuple4(fx, fy, cx, cy)
extr = vtkDoubleArray()
extr.SetName("CameraExtrinsics")
extr.SetNumberOfComponents(12)
extr.InsertNextTuple(list(np.hstack([R, t[:, None]]).reshape(-1)))
size = vtkIntArray()
size.SetName("CameraImageSize")
size.SetNumberOfComponents(2)
size.InsertNextTuple2(W, H)
for a in (intr, extr, size):
    fd.AddArray(a)

lossless = os.path.join(workdir, "scene_lossless")
writer = vtkMLIWriter()
writer.SetInputData(collection)
writer.SetFileName(lossless)
writer.SetFormatToLossless()
assert writer.Write() == 1, "lossless write failed"
assert sorted(os.listdir(lossless))[-1] == "meta.json", os.listdir(lossless)

# --- read it back -------------------------------------------------------------------------------
reader = vtkMLIReader()
assert reader.CanReadFile(lossless) == 1
reader.SetFileName(lossless)
reader.Update()
out = reader.GetOutput()
assert out.GetNumberOfPartitionedDataSets() == L, out.GetNumberOfPartitionedDataSets()
assembly = out.GetDataAssembly()
for k in range(L):
    name = f"Layer{k:02d}"
    assert out.GetMetaData(k).Get(vtkCompositeDataSet.NAME()) == name
    assert assembly.GetFirstNodeByPath(f"/MLI/Layers/{name}") >= 0, name
    layer = out.GetPartitionedDataSet(k).GetPartition(0)
    assert layer.GetClassName() == "vtkPolyData"
    assert layer.GetNumberOfPoints() == W * H, layer.GetNumberOfPoints()
    assert layer.GetNumberOfPolys() == 2 * (W - 1) * (H - 1), layer.GetNumberOfPolys()
    pdata = layer.GetPointData()
    rgba = vtk_to_numpy(pdata.GetScalars())
    assert pdata.GetScalars().GetName() == "RGBA" and rgba.dtype == np.uint8
    expected_rgba = np.floor(255.0 * np.concatenate(
        [colors[k].reshape(-1, 3), alphas[k].reshape(-1, 1)], axis=1).astype(np.float64) + 0.5)
    if k == 0:
        expected_rgba[:, 3] = 255  # the farthest layer is opaque on display; Alpha is exact
    assert np.array_equal(rgba, expected_rgba.astype(np.uint8)), (rgba[:3], expected_rgba[:3])
    assert np.array_equal(vtk_to_numpy(pdata.GetArray("Color")), colors[k].reshape(-1, 3))
    assert np.array_equal(vtk_to_numpy(pdata.GetArray("Alpha")), alphas[k].reshape(-1))
    assert np.array_equal(vtk_to_numpy(pdata.GetArray("Depth")), depths[k].reshape(-1))
    points = vtk_to_numpy(layer.GetPoints().GetData()).astype(np.float64)
    assert np.allclose(points, world_points(depths[k]), rtol=1e-5, atol=1e-5), "points"
    tc = vtk_to_numpy(pdata.GetTCoords())
    assert np.allclose(tc[W + 1], [1 / (W - 1), 1 - 1 / (H - 1)]), tc[W + 1]
fd = out.GetFieldData()
assert fd.GetArray("CameraIntrinsics").GetTuple4(0) == (fx, fy, cx, cy)
assert np.array_equal(np.array(fd.GetArray("CameraExtrinsics").GetTuple(0)),
                      np.hstack([R, t[:, None]]).reshape(-1))
assert fd.GetArray("CameraImageSize").GetTuple2(0) == (W, H)
assert fd.GetArray("NumberOfLayers").GetValue(0) == L

# JPEG form: readable, same layout, colours within JPEG error.
jpeg = os.path.join(workdir, "scene_jpeg")
writer.SetFileName(jpeg)
writer.SetFormatToJpeg()
assert writer.Write() == 1
assert os.path.exists(os.path.join(jpeg, "layer_alpha_01.jpg"))
reader.SetFileName(os.path.join(jpeg, "meta.json"))
reader.Update()
out = reader.GetOutput()
assert out.GetNumberOfPartitionedDataSets() == L
depth1 = vtk_to_numpy(out.GetPartitionedDataSet(1).GetPartition(0).GetPointData().GetArray("Depth"))
step = (depths[1].max() - depths[1].min()) / 255.0
err = np.abs(depth1 - depths[1].reshape(-1)).max()
assert err <= 3 * step, ("JPEG depth error", err, step)  # < 1 step of decoding + JPEG rounding

# --- bad input: reported, the request fails, no crash -------------------------------------------
errors = []


def record(obj, event, message):
    errors.append(message)


record.CallDataType = "string0"
bad = vtkMLIReader()
bad.AddObserver("ErrorEvent", record)
bad.GetExecutive().AddObserver("ErrorEvent", lambda o, e: None)  # mute the executive's echo
bad.SetFileName(os.path.join(workdir, "no_such_mli"))
assert bad.GetExecutive().Update() == 0
assert any("no_such_mli" in e and "does not exist" in e for e in errors), errors
os.makedirs(os.path.join(workdir, "broken"))
with open(os.path.join(workdir, "broken", "meta.json"), "w") as f:
    f.write('{"frame_size": [4, ')
bad.SetFileName(os.path.join(workdir, "broken"))
assert bad.GetExecutive().Update() == 0
assert any("meta.json" in e and "not valid JSON" in e for e in errors), errors
assert bad.GetOutput().GetNumberOfPartitionedDataSets() == 0

# The writer refuses a collection without the camera, and writes nothing.
collection.GetFieldData().RemoveArray("CameraIntrinsics")
bad_writer = vtkMLIWriter()
bad_writer.AddObserver("ErrorEvent", record)
bad_writer.GetExecutive().AddObserver("ErrorEvent", lambda o, e: None)
bad_writer.SetInputData(collection)
bad_writer.SetFileName(os.path.join(workdir, "not_written"))
assert bad_writer.Write() == 0
assert any("CameraIntrinsics" in e and "missing" in e for e in errors), errors
assert not os.path.exists(os.path.join(workdir, "not_written"))

# --- image quality against numpy ----------------------------------------------------------------


def to_image(pixels):
    img = vtkImageData()
    h, w, _ = pixels.shape
    img.SetDimensions(w, h, 1)
    arr = numpy_to_vtk(pixels[::-1].reshape(-1, 3).copy(), deep=1)  # VTK rows start at the bottom
    arr.SetName("RGB")
    img.GetPointData().SetScalars(arr)
    return img


h, w = 50, 64
truth = rng.integers(0, 256, (h, w, 3), dtype=np.uint8)
rendered = np.clip(truth.astype(int) + rng.integers(-12, 13, (h, w, 3)), 0, 255).astype(np.uint8)
quality = vtkSIMPLIImageQuality()
quality.SetInputDataObject(0, to_image(rendered))
quality.SetInputDataObject(1, to_image(truth))
quality.Update()
table = quality.GetOutput()
assert table.GetNumberOfRows() == 3, table.GetNumberOfRows()
assert [table.GetColumnByName("View").GetValue(i) for i in range(3)] == ["0", "mean", "std"]
side = (1 - math.sqrt(0.9)) / 2
my, mx = math.floor(h * side + 0.5), math.floor(w * side + 0.5)
a = rendered[my:h - my, mx:w - mx].astype(np.float64) / 255.0
b = truth[my:h - my, mx:w - mx].astype(np.float64) / 255.0
a = a.astype(np.float32).astype(np.float64)  # the filter compares float32 values
b = b.astype(np.float32).astype(np.float64)
psnr = 10 * math.log10(1.0 / np.mean((a - b) ** 2))
got = table.GetColumnByName("PSNR").GetValue(0)
assert abs(got - psnr) < 1e-9, (got, psnr)
ssim = table.GetColumnByName("SSIM").GetValue(0)
assert 0.0 < ssim < 1.0, ssim
quality.SetInputDataObject(1, to_image(rendered))
quality.Update()
assert math.isinf(quality.GetOutput().GetColumnByName("PSNR").GetValue(0))
assert abs(quality.GetOutput().GetColumnByName("SSIM").GetValue(0) - 1.0) < 1e-12

print("MLI python OK: layers", L, "points", W * H, "PSNR", round(psnr, 3), "SSIM", round(ssim, 4))
