#!/usr/bin/env bash
# The ParaView GUI test of issue 11 item 5: starts the real GUI (under the test run's X server)
# with the plugin loaded at start-up, builds the MLI of a bundled scene there and shows it,
# setting nothing (gui_mli.py checks the colouring, translucency and camera the plugin chose),
# then compares the GUI's screenshot with `simpli render` of the same MLI at the same camera
# (PSNR over the central 80 %: the GUI draws its orientation axes in a corner), and checks that
# the SIMPLI menu entries exist.
#   gui_mli.sh PARAVIEW PLUGIN_DIR SIMPLI SCENE WEIGHTS WORKDIR
set -euo pipefail
paraview=$1 plugin_dir=$2 simpli=$3 scene=$4 weights=$5 workdir=$6
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
rm -rf "$workdir"
mkdir -p "$workdir"
fail() { echo "FAIL: $*"; exit 1; }

status=0
SIMPLI_GUI_WORKDIR=$workdir SIMPLI_GUI_SCENE=$scene SIMPLI_GUI_WEIGHTS=$weights \
  SIMPLI_GUI_MENU_DUMP=$workdir/menus.txt PV_PLUGIN_PATH=$plugin_dir \
  timeout 600 "$paraview" --plugins=SimpliPlugin --script="$here/gui_mli.py" \
  > "$workdir/paraview.log" 2>&1 || status=$?
cat "$workdir/gui.log" 2>/dev/null || true
((status == 0)) || fail "the GUI exited with $status (log: $workdir/paraview.log)"
grep -qx PASS "$workdir/gui.log" || fail "gui_mli.py did not pass"

for entry in "Filters/SIMPLI/SIMPLI Build MLI" "Filters/SIMPLI/SIMPLI Render View" \
             "Filters/SIMPLI/SIMPLI Image Quality" "Sources/SIMPLI/SIMPLI Train" \
             "Sources/SIMPLI/SIMPLI Layer Grid" "SIMPLI/Apply MLI Reference Camera"; do
  grep -qxF "$entry" "$workdir/menus.txt" ||
    fail "menu entry '$entry' missing; the SIMPLI entries are: $(tr '\n' ';' < "$workdir/menus.txt")"
done
echo "menus OK: $(wc -l < "$workdir/menus.txt") SIMPLI entries"

"$simpli" render "$workdir/built.mli" --out "$workdir/render" > "$workdir/render.log" 2>&1 ||
  fail "simpli render failed: $(tail -3 "$workdir/render.log")"
reference=$(find "$workdir/render" -name '*.png' ! -name '*depth*' | sort | head -1)
[[ -n "$reference" ]] || fail "simpli render wrote no colour PNG in $workdir/render"
/usr/bin/python3 - "$workdir/gui.png" "$reference" <<'PY'
import math
import sys

from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader


def read(png):
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)
    return pixels[:, :, :3].astype(float)


gui, render = read(sys.argv[1]), read(sys.argv[2])
if gui.shape != render.shape:
    print(f"FAIL: screenshot {gui.shape} vs render {render.shape}")
    sys.exit(1)
h, w, _ = gui.shape
crop = (slice(h // 10, h - h // 10), slice(w // 10, w - w // 10))
mse = float(((gui[crop] - render[crop]) ** 2).mean())
psnr = 10 * math.log10(255.0 ** 2 / max(mse, 1e-12))
# Threshold: the GUI blends 8-bit RGBA per vertex with depth peeling where the rasterizer
# composites float texels; a wrong camera, colour map or layer order scores far below.
threshold = 30.0
print(f"GUI screenshot vs simpli render: PSNR {psnr:.2f} dB over the central 80 % "
      f"(threshold {threshold})")
sys.exit(0 if psnr >= threshold else 1)
PY
echo PASS
