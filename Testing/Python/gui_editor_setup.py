"""GUI test of the Gaussian widget editor (the GaussianWidgets rows of the Properties
panel), part 1 (run by `paraview --script=` before gui_editor_click.xml edits the widgets).
A synthetic volume whose ReducedCoordinates are the voxel positions (-20..20 on each
axis) is shown as a Gaussian TF Volume with one widget; every change of GaussianWidgets
and of GaussianWidgetsHidden is recorded into $MCV_GUI_STATE for gui_editor_check.py.
After the last edit a screenshot of the whole screen goes to $MCV_OUTPUT_DIR (or to
$MCV_EDITOR_SCREENSHOT, for the README's picture)."""
import json
import os
import subprocess

from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce

out = os.environ.get("MCV_OUTPUT_DIR", ".")
os.makedirs(out, exist_ok=True)
state_file = os.environ.get("MCV_GUI_STATE") or os.path.join(out, "gui_editor_state.json")
screenshot = os.environ.get("MCV_EDITOR_SCREENSHOT") or os.path.join(out, "gui_editor.png")
# The click script makes this many edits; the screenshot follows the last one.
EDITS = 7

wavelet = Wavelet(WholeExtent=[-20, 20, -20, 20, -20, 20])
coords = Calculator(Input=wavelet, Function="coords", ResultArrayName="ReducedCoordinates",
                    ResultArrayType="Float")
RenameSource("ReducedVolume", coords)
view = GetActiveViewOrCreate("RenderView")
display = mce.show_gaussian_tf(coords, view, widgets=[0, 0, 0, 4, 1, 0.4, 0.1, 0.8])
ResetCamera(view)
Render(view)
# The Properties panel shows the active source's display: the editor.
SetActiveSource(coords)

state = {"states": [], "hidden": []}


def save():
    with open(state_file, "w") as f:
        json.dump(state, f, indent=1)


def take_screenshot():
    # In the background: the GUI repaints while the click script waits (process_events).
    subprocess.Popen("sleep 2; xwd -root -silent | convert xwd:- '%s'" % screenshot,
                     shell=True)


def record(*unused):
    state["states"].append([float(v) for v in display.GaussianWidgets])
    save()
    if len(state["states"]) == EDITS:
        take_screenshot()


def record_hidden(*unused):
    state["hidden"].append([float(v) for v in display.GaussianWidgetsHidden])
    save()


display.SMProxy.GetProperty("GaussianWidgets").AddObserver("ModifiedEvent", record)
display.SMProxy.GetProperty("GaussianWidgetsHidden").AddObserver("ModifiedEvent", record_hidden)
save()
