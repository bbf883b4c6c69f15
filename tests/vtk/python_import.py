"""The Python wrapping of Simpli::Filters, as a user sees it from /usr/bin/python3.

usage: python_import.py EXPECTED_ROOT
EXPECTED_ROOT is where the `simpli` package must come from (the build tree or an install
prefix), so that a stale copy elsewhere on sys.path cannot make the test pass.
"""
import os
import sys

import vtkmodules.all  # noqa: F401  (the whole of VTK first, as users do)
from simpli import (vtkSIMPLIBuildMLI, vtkSIMPLILayerGridSource, vtkSIMPLIRenderView,
                    vtkSIMPLISceneReader, vtkSIMPLITrain)
import simpli

expected_root = os.path.realpath(sys.argv[1])
package_file = os.path.realpath(simpli.__file__)
assert package_file.startswith(expected_root + os.sep), (
    f"simpli was imported from {package_file}, expected under {expected_root}")

# The scene reader and the render view are wrapped too (their tests: python_scene_render.py).
assert vtkSIMPLISceneReader().GetOutputPortInformation(1) is not None
assert vtkSIMPLIRenderView().GetNumberOfInputPorts() == 2
# The network filters too (their tests: python_network.py): properties reach the C++ objects.
build = vtkSIMPLIBuildMLI()
build.SetSourceViews("0,2")
assert build.GetSourceViews() == "0,2" and build.GetRandomSeed() == -1
assert build.GetDepthRange() == vtkSIMPLIBuildMLI.DEPTH_RANGE_CONFIG
train = vtkSIMPLITrain()
assert train.GetNumberOfInputPorts() == 0 and train.GetSteps() == -1

src = vtkSIMPLILayerGridSource()
src.SetWidth(6)
src.SetHeight(3)
src.SetDepth(4.0)
src.SetFx(2.0)
src.SetFy(0.5)
src.SetCx(0.25)
src.SetCy(0.75)
src.SetColor(0.2, 0.4, 0.8, 1.0)
assert src.GetColor() == (0.2, 0.4, 0.8, 1.0), src.GetColor()
src.Update()
out = src.GetOutput()
assert out.GetClassName() == "vtkPolyData"
assert out.GetNumberOfPoints() == 18, out.GetNumberOfPoints()
assert out.GetNumberOfPolys() == 2 * 5 * 2, out.GetNumberOfPolys()
pd = out.GetPointData()
names = sorted(pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays()))
assert names == ["Alpha", "Color", "Depth", "RGBA", "TCoords"], names
assert pd.GetScalars().GetName() == "RGBA"
assert pd.GetScalars().GetTuple4(7) == (51.0, 102.0, 204.0, 255.0), pd.GetScalars().GetTuple4(7)
# Last vertex: u = v = 1 -> 4 * ((1 - 0.25) / 2, (1 - 0.75) / 0.5, 1) = (1.5, 2, 4).
last = out.GetPoint(17)
assert all(abs(a - b) < 1e-6 for a, b in zip(last, (1.5, 2.0, 4.0))), last

# Bad input: the error reaches a Python observer, names the property and the request fails.
errors = []


def record_message(obj, event, message):
    errors.append(message)


record_message.CallDataType = "string0"  # VTK passes the message text as call data
src.AddObserver("ErrorEvent", record_message)
# The executive reports the failed request too; observing it keeps the test output clean.
executive_events = []
src.GetExecutive().AddObserver("ErrorEvent", lambda obj, event: executive_events.append(event))
src.SetDepth(-1.0)
assert src.GetExecutive().Update() == 0, "a negative Depth must fail the request"
assert any("Depth" in e and "-1" in e for e in errors), errors
assert src.GetOutput().GetNumberOfPoints() == 0
assert executive_events, "the executive did not report the failed request"

print("simpli", package_file, "OK")
