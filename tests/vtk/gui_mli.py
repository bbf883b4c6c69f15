"""Run inside the ParaView GUI (paraview --plugins=SimpliPlugin --script=gui_mli.py) by
gui_mli.sh: builds the MLI of a bundled scene with SIMPLIBuildMLI and shows it in the GUI's
render view, setting nothing else, as a user would. The plugin's GUI part must have shown it as
captured: colours = the RGBA point scalars directly (MapScalars off), depth peeling with a peel
per layer, the camera at the MLI's reference camera. Saves the screenshot and the MLI (lossless)
for gui_mli.sh to compare with `simpli render`. The GUI keeps running after a script, so the
script ends the process itself: exit 0 when every check passed, 1 otherwise, with the reasons
in $SIMPLI_GUI_WORKDIR/gui.log (a Python error in the GUI would open a dialog and hang).
"""
import os
import traceback

workdir = os.environ["SIMPLI_GUI_WORKDIR"]
log = open(os.path.join(workdir, "gui.log"), "w")


def finish(code, message):
    log.write(message + "\n")
    log.flush()
    os._exit(code)


try:
    import numpy as np
    from paraview.simple import GetActiveViewOrCreate, Render, SaveData, SaveScreenshot, Show
    import paraview.simple as pvs

    if not hasattr(pvs, "SIMPLIBuildMLI"):
        finish(1, "FAIL: SIMPLIBuildMLI is not defined: the plugin was not loaded at start-up")
    build = pvs.SIMPLIBuildMLI(SceneFileName=os.environ["SIMPLI_GUI_SCENE"],
                               WeightsFile=os.environ["SIMPLI_GUI_WEIGHTS"],
                               SourceViews="0,4,8")
    view = GetActiveViewOrCreate("RenderView")
    display = Show(build, view)
    Render(view)

    mli = build.GetClientSideObject().GetOutputDataObject(0)
    layers = mli.GetNumberOfPartitionedDataSets()
    fd = mli.GetFieldData()
    E = np.array(fd.GetArray("CameraExtrinsics").GetTuple(0)).reshape(3, 4)
    W, H = (int(v) for v in fd.GetArray("CameraImageSize").GetTuple(0))
    centre = -E[:, :3].T @ E[:, 3]
    problems = []
    if list(display.ColorArrayName) != ["POINTS", "RGBA"]:
        problems.append(f"coloured by {list(display.ColorArrayName)}, expected POINTS RGBA")
    if display.MapScalars != 0:
        problems.append("MapScalars is on: the RGBA would go through a colour map")
    if view.GetPropertyValue("DepthPeeling") != 1 or view.MaximumNumberOfPeels < layers + 1:
        problems.append(f"depth peeling {view.GetPropertyValue('DepthPeeling')} with "
                        f"{view.MaximumNumberOfPeels} peels for {layers} layers")
    position = np.array(view.CameraPosition)
    forward = np.array(view.CameraFocalPoint) - position
    forward /= np.linalg.norm(forward)
    if np.abs(position - centre).max() > 1e-6 or np.abs(forward - E[2, :3]).max() > 1e-6:
        problems.append(f"camera at {position} looking along {forward}: expected the MLI "
                        f"reference camera at {centre} looking along {E[2, :3]}")
    SaveScreenshot(os.path.join(workdir, "gui.png"), view, ImageResolution=[W, H])
    SaveData(os.path.join(workdir, "built.mli"), proxy=build, Format="Lossless")
    log.write(f"MLI: {layers} layers of {W} x {H}; camera {view.CameraPosition}, view angle "
              f"{view.CameraViewAngle:.3f}\n")
    if problems:
        finish(1, "FAIL: " + "; ".join(problems))
    finish(0, "PASS")
except Exception:
    traceback.print_exc(file=log)
    finish(1, "FAIL: the script raised")
