"""The MLI proxies of SimpliPlugin in pvpython: reader, writer, image quality, and a render.

usage: pv_mli.py --plugin SO --workdir DIR
Writes a two-layer MLI with the `simpli` Python package (PYTHONPATH = the build tree): a far
opaque blue layer filling the reference view and a near red layer that is opaque only in the
centre. Then, in ParaView: reads it with SIMPLIMLIReader (properties, hints, data, field-data
camera), opens it through the reader factory (meta.json), saves it with the writer proxy
(.mli, Lossless) and compares, renders it from the reference camera with MapScalars off and
checks pixels (centre red, the front layer's transparent part shows blue, outside black), and
runs SIMPLIImageQuality on screenshots. Renders, so it needs an X server (xvfb-run).
"""
import argparse
import math
import os
import shutil
import sys

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--workdir", required=True)
args = parser.parse_args()




sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pv_support import fail, hold_x_display  # noqa: E402

x_connection = hold_x_display()

import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import (vtkPartitionedDataSetCollection,  # noqa: E402
                                           vtkPolyData)

from simpli import vtkMLIWriter  # noqa: E402

from paraview import servermanager  # noqa: E402
from paraview.simple import (ColorBy, CreateRenderView, Hide, LoadPlugin,  # noqa: E402
                             OpenDataFile, Render, SaveData, SaveScreenshot, Show)
import paraview.simple as pvs  # noqa: E402

shutil.rmtree(args.workdir, ignore_errors=True)
os.makedirs(args.workdir)

# --- the MLI: identity reference camera, fx = fy = 1, principal point at the centre ------------
N = 16  # texels per side
u = np.arange(N) / (N - 1)
uu, vv = np.meshgrid(u, u)  # uu varies along a row (j), vv down the rows (i)
far = dict(depth=np.full((N, N), 4.0), color=(0.0, 0.0, 1.0), alpha=np.ones((N, N)))
centre = (np.abs(uu - 0.5) <= 0.25) & (np.abs(vv - 0.5) <= 0.25)
near = dict(depth=np.full((N, N), 2.0), color=(1.0, 0.0, 0.0), alpha=centre.astype(float))

collection = vtkPartitionedDataSetCollection()
for k, layer in enumerate((far, near)):
    d = layer["depth"]
    pts = np.stack([d * (uu - 0.5), d * (vv - 0.5), d], axis=-1).reshape(-1, 3)
    pd = vtkPolyData()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(pts, deep=1))
    pd.SetPoints(points)
    color = np.tile(np.array(layer["color"], dtype=np.float32), (N * N, 1))
    for name, values in (("Color", color), ("Alpha", layer["alpha"].reshape(-1)),
                         ("Depth", d.reshape(-1))):
        a = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float32), deep=1)
        a.SetName(name)
        pd.GetPointData().AddArray(a)
    collection.SetPartition(k, 0, pd)
intr = vtkDoubleArray()
intr.SetName("CameraIntrinsics")
intr.SetNumberOfComponents(4)
intr.InsertNextTuple4(1.0, 1.0, 0.5, 0.5)
extr = vtkDoubleArray()
extr.SetName("CameraExtrinsics")
extr.SetNumberOfComponents(12)
extr.InsertNextTuple([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0])
size = vtkIntArray()
size.SetName("CameraImageSize")
size.SetNumberOfComponents(2)
size.InsertNextTuple2(N, N)
for a in (intr, extr, size):
    collection.GetFieldData().AddArray(a)
mli = os.path.join(args.workdir, "two_layers")
writer = vtkMLIWriter()
writer.SetInputData(collection)
writer.SetFileName(mli)
writer.SetFormatToLossless()
if writer.Write() != 1:
    fail("writing the test MLI failed")

# --- reader proxy ----------------------------------------------------------------------------------
LoadPlugin(args.plugin, ns=globals())
if "SIMPLIMLIReader" not in globals():
    fail("SIMPLIMLIReader is not defined: the plugin did not load")
reader = SIMPLIMLIReader(FileName=mli)  # noqa: F821  (defined by LoadPlugin)
props = set(reader.ListProperties())
expected = {"FileName", "DropTransparentTriangles", "SkipEmptyLayers", "AlphaThreshold",
            "DepthDecoding", "MeshMode", "MeshTolerance"}
if not expected <= props:
    fail(f"reader lacks properties {sorted(expected - props)}")
hints = reader.SMProxy.GetHints()
menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
if menu is None or menu.GetAttribute("category") != "SIMPLI":
    fail("SIMPLI MLI Reader is not in the SIMPLI menu")
file_hints = reader.SMProxy.GetProperty("FileName").GetHints()
if file_hints is None or file_hints.FindNestedElementByName("UseDirectoryName") is None:
    fail("FileName has no UseDirectoryName hint (the file dialog would not pick folders)")
reader.UpdatePipeline()
info = reader.GetDataInformation()
if info.GetNumberOfPoints() != 2 * N * N:
    fail(f"{info.GetNumberOfPoints()} points, expected {2 * N * N}")
if info.GetNumberOfCells() != 2 * 2 * (N - 1) * (N - 1):
    fail(f"{info.GetNumberOfCells()} cells")
for name in ("RGBA", "Color", "Alpha", "Depth"):
    if name not in reader.PointData.keys():
        fail(f"point array {name} missing: {reader.PointData.keys()}")
# The builtin session (pvpython) holds the VTK objects in this process. (servermanager.Fetch
# cannot gather a vtkPartitionedDataSetCollection: it reduces into a vtkMultiBlockDataSet.)
local = reader.GetClientSideObject().GetOutputDataObject(0)
if local.GetClassName() != "vtkPartitionedDataSetCollection":
    fail(f"fetched a {local.GetClassName()}")
if local.GetNumberOfPartitionedDataSets() != 2:
    fail(f"{local.GetNumberOfPartitionedDataSets()} layers")
fd = local.GetFieldData()
if fd.GetArray("CameraIntrinsics").GetTuple4(0) != (1.0, 1.0, 0.5, 0.5):
    fail(f"intrinsics {fd.GetArray('CameraIntrinsics').GetTuple4(0)}")
if fd.GetArray("CameraImageSize").GetTuple2(0) != (N, N):
    fail("image size")
front = local.GetPartitionedDataSet(1).GetPartition(0)
rgba = vtk_to_numpy(front.GetPointData().GetArray("RGBA"))
centre_id = (N // 2) * N + N // 2
if tuple(rgba[centre_id]) != (255, 0, 0, 255) or tuple(rgba[0]) != (255, 0, 0, 0):
    fail(f"front layer RGBA {rgba[centre_id]} {rgba[0]}")
print("reader OK:", info.GetNumberOfPoints(), "points, arrays", reader.PointData.keys())

# --- adaptive meshes: fewer triangles, texture coordinates, the texels in the field data ----------
reader.MeshMode = "Adaptive"
reader.MeshTolerance = 0.5
reader.UpdatePipeline()
adaptive = reader.GetClientSideObject().GetOutputDataObject(0)
cells = sum(adaptive.GetPartitionedDataSet(k).GetPartition(0).GetNumberOfCells() for k in range(2))
if not 0 < cells < 2 * 2 * (N - 1) * (N - 1):
    fail(f"adaptive layers have {cells} triangles")
layer = adaptive.GetPartitionedDataSet(1).GetPartition(0)
if layer.GetPointData().GetTCoords() is None:
    fail("adaptive layer without TCoords")
texture = layer.GetFieldData().GetArray("TextureRGBA")
if texture is None or texture.GetNumberOfTuples() != N * N:
    fail(f"adaptive layer TextureRGBA {texture and texture.GetNumberOfTuples()}")
print("adaptive OK:", cells, "triangles")
reader.MeshMode = "Per Texel"
reader.UpdatePipeline()

# --- reader factory: File > Open on meta.json picks the MLI reader ----------------------------------
opened = OpenDataFile(os.path.join(mli, "meta.json"))
if opened is None or opened.GetXMLName() != "SIMPLIMLIReader":
    fail(f"OpenDataFile(meta.json) gave {opened and opened.GetXMLName()}")
opened.UpdatePipeline()
if opened.GetDataInformation().GetNumberOfPoints() != 2 * N * N:
    fail("meta.json opened, but the data differ")

# --- writer proxy: Save Data as .mli, lossless, then compare ----------------------------------------
copy = os.path.join(args.workdir, "copy.mli")
SaveData(copy, proxy=reader, Format="Lossless")
if not os.path.exists(os.path.join(copy, "layer_rgba_01.tiff")):
    fail(f"SaveData did not write a lossless MLI: {os.listdir(args.workdir)}")
again = SIMPLIMLIReader(FileName=copy)  # noqa: F821
again.UpdatePipeline()
copied = again.GetClientSideObject().GetOutputDataObject(0)
for k in range(2):
    a = vtk_to_numpy(local.GetPartitionedDataSet(k).GetPartition(0).GetPointData().GetArray("Color"))
    b = vtk_to_numpy(copied.GetPartitionedDataSet(k).GetPartition(0).GetPointData().GetArray("Color"))
    if not np.array_equal(a, b):
        fail(f"layer {k} colours differ after Save Data")
print("writer OK:", copy)

# --- render from the reference camera (90 degree view angle) -----------------------------------------
# x/z in [-0.5, 0.5] covers columns and rows 64..192 of 256: the far layer. The near layer is
# opaque for |u - 0.5| <= 0.25 (about columns 98..158) and transparent beyond one texel more.
SIZE = 256
view = CreateRenderView()
view.ViewSize = [SIZE, SIZE]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [0.0, 0.0, 0.0]
display = Show(reader, view)
ColorBy(display, ("POINTS", "RGBA"))
display.MapScalars = 0
display.Ambient, display.Diffuse, display.Specular = 1.0, 0.0, 0.0
Render(view)  # paraview.simple resets the camera on the first render
view.CameraPosition = [0.0, 0.0, 0.0]
view.CameraFocalPoint = [0.0, 0.0, 1.0]
view.CameraViewUp = [0.0, -1.0, 0.0]
view.CameraViewAngle = 90.0
view.CameraParallelProjection = 0
Render(view)
png = os.path.join(args.workdir, "two_layers.png")
SaveScreenshot(png, view, ImageResolution=[SIZE, SIZE])

from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402

png_reader = vtkPNGReader()
png_reader.SetFileName(png)
png_reader.Update()
image = png_reader.GetOutput()


def pixel(col, row_from_top):
    y = SIZE - 1 - row_from_top  # vtkPNGReader puts row 0 at the bottom
    return tuple(image.GetScalarComponentAsDouble(col, y, 0, c) for c in range(3))


red, blue, black = (255.0, 0.0, 0.0), (0.0, 0.0, 255.0), (0.0, 0.0, 0.0)
checks = [("centre: the opaque front layer", 128, 128, red),
          ("front layer, near its edge", 104, 150, red),
          ("left: front transparent, far layer", 72, 128, blue),
          ("top: front transparent, far layer", 128, 72, blue),
          ("bottom right inside the far layer", 185, 185, blue),
          ("outside the reference view", 30, 30, black),
          ("right of the far layer", 215, 128, black)]
bad = []
for what, col, row, want in checks:
    got = pixel(col, row)
    if any(abs(g - w) > 2.0 for g, w in zip(got, want)):
        bad.append(f"{what} ({col}, {row} from top): got {got}, expected {want}")
if bad:
    fail("pixel check failed for " + png + ":\n  " + "\n  ".join(bad))
print("render OK:", png)

# --- image quality on screenshots ----------------------------------------------------------------------
view.Background = [1.0, 1.0, 1.0]
Render(view)
png_white = os.path.join(args.workdir, "two_layers_white.png")
SaveScreenshot(png_white, view, ImageResolution=[SIZE, SIZE])
Hide(reader, view)

rendered = pvs.PNGSeriesReader(FileNames=[png_white])
truth = pvs.PNGSeriesReader(FileNames=[png])
quality = SIMPLIImageQuality(Input=rendered, GroundTruth=truth)  # noqa: F821
if not {"Input", "GroundTruth", "CropAreaFraction", "MaxValue"} <= set(quality.ListProperties()):
    fail(f"image quality properties {quality.ListProperties()}")
quality.UpdatePipeline()
table = servermanager.Fetch(quality)
if table.GetNumberOfRows() != 3:
    fail(f"quality table has {table.GetNumberOfRows()} rows")
# Only the background differs: black vs white outside the far layer. In the central crop
# (columns and rows 7..248) that is 242^2 - 128^2 pixels (the layer covers pixels 64..191) with all
# three channels off by 1: MSE = (242^2 - 128^2) / 242^2.
psnr = table.GetColumnByName("PSNR").GetValue(0)
expected_psnr = 10 * math.log10(242.0 ** 2 / (242.0 ** 2 - 128.0 ** 2))
if abs(psnr - expected_psnr) > 0.05:
    fail(f"PSNR {psnr}, expected about {expected_psnr}")
ssim = table.GetColumnByName("SSIM").GetValue(0)
if not 0.0 < ssim < 0.9:
    fail(f"SSIM {ssim}")
quality.GroundTruth = rendered
quality.UpdatePipeline()
table = servermanager.Fetch(quality)
if not math.isinf(table.GetColumnByName("PSNR").GetValue(0)):
    fail("PSNR of identical screenshots is not inf")
print(f"image quality OK: PSNR {psnr:.3f} (expected {expected_psnr:.3f}), SSIM {ssim:.4f}")
