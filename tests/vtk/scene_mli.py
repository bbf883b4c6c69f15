"""Shared by python_scene_render.py and pv_scene_render.py: an MLI built from one view of a
scene read by vtkSIMPLISceneReader (its image and its ground-truth depth map).

The MLI has one opaque layer whose texel (i, j) holds pixel (i, j) of the view, at the pixel's
depth. Its camera is the view's camera with intrinsics re-expressed for the corner grid
(texel j on u' = j / (W - 1), spec §1.3): u = (j + 0.5) / W must equal
u' = j / (W - 1), so fx' = fx W / (W - 1), cx' = (cx W - 0.5) / (W - 1) (same for y). Rendered
at the view's own camera, every pixel centre then falls exactly on a vertex.
"""
import os

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPartitionedDataSetCollection, vtkPolyData
from vtkmodules.vtkIOImage import vtkPNGReader


def view_camera(image):
    """(fx, fy, cx, cy), 3x4 [R|t] and (W, H) from a scene view's field data."""
    fd = image.GetFieldData()
    k = fd.GetArray("CameraIntrinsics").GetTuple(0)
    e = np.array(fd.GetArray("CameraExtrinsics").GetTuple(0)).reshape(3, 4)
    size = tuple(int(v) for v in fd.GetArray("CameraImageSize").GetTuple(0))
    return k, e, size


def view_rgb(image):
    """The view's pixels as an H x W x 3 uint8 array, row 0 = top."""
    w, h = image.GetDimensions()[:2]
    return vtk_to_numpy(image.GetPointData().GetArray("RGB")).reshape(h, w, 3)[::-1]


def read_depth(scene_dir, view_name, scale):
    """Ground-truth depth of a datasets_small view (16-bit PNG, 0.001 scene units per count),
    in the reader's (normalised) units. Row 0 = top."""
    reader = vtkPNGReader()
    reader.SetFileName(os.path.join(scene_dir, "depth", view_name))
    reader.Update()
    img = reader.GetOutput()
    w, h = img.GetDimensions()[:2]
    d = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w).astype(np.float64)[::-1]
    return d * 0.001 * scale


def mli_collection(image, depth):
    """A one-layer MLI collection in vtkMLIWriter's input layout."""
    (fx, fy, cx, cy), E, (W, H) = view_camera(image)
    fxc, cxc = fx * W / (W - 1), (cx * W - 0.5) / (W - 1)
    fyc, cyc = fy * H / (H - 1), (cy * H - 0.5) / (H - 1)
    rgb = view_rgb(image).reshape(-1, 3).astype(np.float32) / 255.0
    v, u = np.meshgrid(np.arange(H) / (H - 1), np.arange(W) / (W - 1), indexing="ij")
    xc = np.stack([depth * (u - cxc) / fxc, depth * (v - cyc) / fyc, depth], axis=-1).reshape(-1, 3)
    R, t = E[:, :3], E[:, 3]
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk((xc - t) @ R, deep=1))  # rows: R^T (x - t)
    pd.SetPoints(pts)
    for name, values in (("Color", rgb), ("Alpha", np.ones(W * H, np.float32)),
                         ("Depth", depth.reshape(-1).astype(np.float32))):
        a = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
        a.SetName(name)
        pd.GetPointData().AddArray(a)
    collection = vtkPartitionedDataSetCollection()
    collection.SetPartition(0, 0, pd)
    intr = vtkDoubleArray()
    intr.SetName("CameraIntrinsics")
    intr.SetNumberOfComponents(4)
    intr.InsertNextTuple4(fxc, fyc, cxc, cyc)
    extr = vtkDoubleArray()
    extr.SetName("CameraExtrinsics")
    extr.SetNumberOfComponents(12)
    extr.InsertNextTuple(list(E.reshape(-1)))
    size = vtkIntArray()
    size.SetName("CameraImageSize")
    size.SetNumberOfComponents(2)
    size.InsertNextTuple2(W, H)
    for a in (intr, extr, size):
        collection.GetFieldData().AddArray(a)
    return collection


def psnr(a, b):
    """PSNR (peak 1) of two uint8 arrays."""
    mse = np.mean((a.astype(np.float64) / 255.0 - b.astype(np.float64) / 255.0) ** 2)
    return float("inf") if mse == 0 else 10.0 * np.log10(1.0 / mse)


def crop(a, fraction=0.9):
    """The paper's central crop keeping `fraction` of the area."""
    h, w = a.shape[:2]
    side = (1 - np.sqrt(fraction)) / 2
    my, mx = int(np.floor(h * side + 0.5)), int(np.floor(w * side + 0.5))
    return a[my:h - my, mx:w - mx]
