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

    from paraview import servermanager

    if not hasattr(pvs, "SIMPLIBuildMLI"):
        finish(1, "FAIL: SIMPLIBuildMLI is not defined: the plugin was not loaded at start-up")
    settings = dict(SceneFileName=os.environ["SIMPLI_GUI_SCENE"],
                    WeightsFile=os.environ["SIMPLI_GUI_WEIGHTS"], SourceViews="0,4,8")
    problems = []

    # Progress and abort as the GUI sees them: the session's progress handler is what feeds
    # the GUI's progress bar (pqProgressManager); an abort sets the filter's AbortExecute.
    handler = servermanager.vtkProcessModule.GetProcessModule().GetSession().GetProgressHandler()
    # The handler forwards at most one event per interval (wall time; ParaView clamps it to
    # >= 0.01 s): at the smallest interval it forwards all but events closer than 10 ms.
    interval = handler.GetProgressInterval()
    handler.SetProgressInterval(0.01)
    aborted = pvs.SIMPLIBuildMLI(**settings)
    seen = []

    def abort_midway(obj, event):
        seen.append((obj.GetLastProgress(), obj.GetLastProgressText() or ""))
        if obj.GetLastProgress() >= 30 and "SIMPLI" in seen[-1][1]:
            aborted.GetClientSideObject().SetAbortExecute(1)

    tag = handler.AddObserver("ProgressEvent", abort_midway)
    aborted.UpdatePipeline()
    handler.RemoveObserver(tag)
    partial = aborted.GetClientSideObject().GetOutputDataObject(0)
    if not any(p >= 30 for p, _ in seen):
        problems.append(f"abort: the GUI saw no progress of 30 % or more ({seen[:5]})")
    if partial is not None and partial.GetNumberOfPartitionedDataSets() != 0:
        problems.append(f"abort: the aborted build left {partial.GetNumberOfPartitionedDataSets()}"
                        " layers (a half-built MLI)")
    log.write(f"abort: {len(seen)} progress events before the abort at "
              f"{max(p for p, _ in seen) if seen else -1} %, output layers "
              f"{partial.GetNumberOfPartitionedDataSets() if partial is not None else 'none'}\n")
    pvs.Delete(aborted)

    progress = []
    tag = handler.AddObserver(
        "ProgressEvent",
        lambda obj, event: progress.append((obj.GetLastProgress(), obj.GetLastProgressText() or "")))
    build = pvs.SIMPLIBuildMLI(**settings)
    # What the filter reports, every event (the builtin session's filter object): the whole
    # range, in order. What the GUI sees is the part the handler forwards, which depends on
    # timing (the meshes' last 10 % take a few ms): many events, in order, past the forward pass.
    reported = []
    filter_tag = build.GetClientSideObject().AddObserver(
        "ProgressEvent", lambda obj, event: reported.append(obj.GetProgress()))
    build.UpdatePipeline()
    build.GetClientSideObject().RemoveObserver(filter_tag)
    handler.RemoveObserver(tag)
    handler.SetProgressInterval(interval)
    if len(reported) < 10 or reported[0] != 0 or reported[-1] != 1 or reported != sorted(reported):
        problems.append(f"progress: the filter reported {len(reported)} events, {reported[:3]} .. "
                        f"{reported[-3:]} (expected >= 10, increasing from 0 to 1)")
    ours = [p for p, text in progress if "SIMPLI" in text]
    if len(ours) < 5 or max(ours) < 80 or ours != sorted(ours):
        problems.append(f"progress: the GUI saw {len(ours)} SIMPLI progress events, "
                        f"{ours[:3]} .. {ours[-3:]} (expected >= 5, increasing, up to >= 80 %)")
    log.write(f"progress: the filter reported {len(reported)} events, the GUI saw {len(ours)} from "
              f"{progress[0][1] if progress else '-'}, {ours[:1]} .. {ours[-1:]} %\n")
    view = GetActiveViewOrCreate("RenderView")
    display = Show(build, view)
    Render(view)

    mli = build.GetClientSideObject().GetOutputDataObject(0)
    layers = mli.GetNumberOfPartitionedDataSets()
    fd = mli.GetFieldData()
    E = np.array(fd.GetArray("CameraExtrinsics").GetTuple(0)).reshape(3, 4)
    W, H = (int(v) for v in fd.GetArray("CameraImageSize").GetTuple(0))
    centre = -E[:, :3].T @ E[:, 3]
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
