"""vtkSIMPLIBuildMLI in parallel, through the plugin's proxies under
`mpiexec -n 2 pvbatch pv_pieces.py --plugin SO --scenes DIR` (each rank runs the pipeline as
piece `rank` of 2): a scene with BuildPiece 0 and another with BuildPiece 1 are each built once,
on their own rank (the data information, summed over the ranks, has one MLI's points; the
"BuildPiece" field data's range names the rank), and BuildPiece -1 builds a copy on every rank
(twice the points). No rendering.
"""
import argparse
import os
import sys

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--scenes", required=True)
args = parser.parse_args()

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pv_support import fail  # noqa: E402

from paraview import servermanager  # noqa: E402
from paraview.simple import LoadPlugin, SetActiveSource  # noqa: E402

LoadPlugin(args.plugin, ns=globals())
ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
if ranks != 2:
    fail(f"expected 2 ranks (mpiexec -n 2 pvbatch), got {ranks}")


def build(scene, piece):
    SetActiveSource(None)  # else paraview.simple connects the last filter as the input
    b = SIMPLIBuildMLI(SceneFileName=os.path.join(args.scenes, scene), Config="tiny",  # noqa: F821
                       RandomSeed=1, SourceViews="0,6", CorrectionSteps=1, BuildPiece=piece)
    b.UpdatePipeline()
    info = b.GetDataInformation().DataInformation
    builder = info.GetFieldDataInformation().GetArrayInformation("BuildPiece")
    if builder is None:
        fail(f"{scene}, BuildPiece {piece}: no BuildPiece field data on any rank")
    return info.GetNumberOfPoints(), tuple(builder.GetComponentRange(0))


points0, built0 = build("scene_00", 0)
points1, built1 = build("scene_01", 1)
copies, built_all = build("scene_00", -1)
print(f"BuildPiece 0: {points0} points, built on {built0}; BuildPiece 1: {points1} points, "
      f"built on {built1}; BuildPiece -1: {copies} points, built on {built_all}")
if points0 <= 0:
    fail("BuildPiece 0: no MLI")
if built0 != (0, 0) or built1 != (1, 1):
    fail(f"built on ranks {built0} and {built1}, expected (0, 0) and (1, 1)")
if points1 != points0:
    fail(f"BuildPiece 1 has {points1} points, one MLI of the same size has {points0}")
if copies != 2 * points0 or built_all != (0, 1):
    fail(f"BuildPiece -1: {copies} points on ranks {built_all}, expected {2 * points0} on (0, 1)")
print("PASS")
