"""Shared by the pvpython / pvbatch tests (tests/vtk/pv_*.py): failing with a message, and
holding an X connection so render tests can run back to back under xvfb-run."""
import ctypes
import ctypes.util
import os
import sys
import time


def fail(message):
    print("FAIL:", message, file=sys.stderr)
    sys.exit(1)


def hold_x_display(timeout=30.0):
    """Connect to $DISPLAY and keep the connection until exit.

    Xvfb resets when its last client leaves and refuses clients during the reset, which makes
    VTK abort ("bad X server connection") when render tests run back to back; holding a
    connection prevents that. Without a display, fail clearly instead of VTK's SIGABRT.
    """
    if not os.environ.get("DISPLAY"):
        fail("no DISPLAY: rendering needs an X server (run the tests under xvfb-run)")
    x11 = ctypes.CDLL(ctypes.util.find_library("X11") or "libX11.so.6")
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
    deadline = time.monotonic() + timeout
    while True:
        handle = x11.XOpenDisplay(None)
        if handle:
            return handle
        if time.monotonic() > deadline:
            fail(f"cannot connect to the X server DISPLAY={os.environ['DISPLAY']}")
        time.sleep(0.05)


def screenshot_from_camera(source, extrinsic, fy, width, height, png):
    """Shows `source`'s point RGBA directly (MapScalars off, unlit) in a new render view whose
    camera is the OpenCV camera [R | t] = `extrinsic` with relative focal length `fy` (principal
    point at the centre), saves a width x height screenshot to `png` and returns its RGB pixels
    as a height x width x 3 array in VTK's row order (bottom row first)."""
    import math

    from paraview.simple import ColorBy, CreateRenderView, Render, SaveScreenshot, Show

    R, t = extrinsic[:, :3], extrinsic[:, 3]
    centre = -R.T @ t
    view = CreateRenderView()
    view.ViewSize = [width, height]
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.0, 0.0, 0.0]
    display = Show(source, view)
    ColorBy(display, ("POINTS", "RGBA"))
    display.MapScalars = 0
    display.Ambient, display.Diffuse, display.Specular = 1.0, 0.0, 0.0
    Render(view)  # paraview.simple resets the camera on the first render
    view.CameraPosition = list(centre)
    view.CameraFocalPoint = list(centre + R[2])
    view.CameraViewUp = list(-R[1])  # OpenCV's y points down
    view.CameraViewAngle = 2.0 * math.degrees(math.atan(0.5 / fy))  # vertical
    view.CameraParallelProjection = 0
    Render(view)
    SaveScreenshot(png, view, ImageResolution=[width, height])
    return read_png_rgb(png, width, height)


def read_png_rgb(png, width, height):
    """The RGB pixels of a width x height PNG as a height x width x 3 array in VTK's row order
    (bottom row first)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader

    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
    return pixels.reshape(height, width, -1)[:, :, :3]
