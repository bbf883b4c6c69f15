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
