"""GUI test of the Gaussian widget editor (the GaussianWidgets rows of the Properties
panel), part 1 (run by `paraview --script=` before gui_editor_click.xml edits the widgets).
A synthetic volume whose ReducedCoordinates are the voxel positions (-20..20 on each
axis) is shown as a Gaussian TF Volume with one widget; every change of GaussianWidgets
and of GaussianWidgetsHidden is recorded into $MCV_GUI_STATE for gui_editor_check.py.
After the last edit a screenshot of the whole screen goes to $MCV_OUTPUT_DIR (or to
$MCV_EDITOR_SCREENSHOT, for the picture in docs/gui.md)."""
import json
import os
import subprocess

from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce

out = os.environ.get("MCV_OUTPUT_DIR", ".")
os.makedirs(out, exist_ok=True)
state_file = os.environ.get("MCV_GUI_STATE") or os.path.join(out, "gui_editor_state.json")
screenshot = os.environ.get("MCV_EDITOR_SCREENSHOT") or os.path.join(out, "gui_editor.png")
# The click script's edits change GaussianWidgets this many times (the last two: Seed from
# clusters, set from Python); the screenshot follows the last one.
EDITS = 11

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


# Without a window manager, -geometry is not always honoured: the window is placed and
# sized here (1600x1000 at the origin), then the left docks are widened by dragging their
# edge (x = 294 in that layout) so that the Properties panel shows the editor unclipped.
SCREENSHOT = """
window=$(xdotool search --onlyvisible --name ParaView 2>/dev/null | head -n 1)
if [ -n "$window" ]; then
  xdotool windowmove "$window" 0 0 windowsize "$window" 1600 1000
  sleep 1
  xdotool mousemove 294 300 sleep 0.3 mousedown 1 sleep 0.3 mousemove 320 300 sleep 0.3 \\
    mousemove 400 300 sleep 0.3 mousemove 470 300 sleep 0.3 mouseup 1
  sleep 2
fi
xwd -root -silent | convert xwd:- '%s'
"""


def take_screenshot():
    # In the background: the GUI repaints while the click script waits (process_events).
    subprocess.Popen("sleep 1;" + SCREENSHOT % screenshot, shell=True)


def record(*unused):
    state["states"].append([float(v) for v in display.GaussianWidgets])
    save()
    if len(state["states"]) == EDITS:
        take_screenshot()


def record_hidden(*unused):
    state["hidden"].append([float(v) for v in display.GaussianWidgetsHidden])
    save()


# The seed button runs auto_widgets through ParaView's Python: record what it returned.
_auto = mce.auto_widgets


def auto(*args, **kwargs):
    seeded = _auto(*args, **kwargs)
    state["seeded"] = [float(v) for v in seeded]
    save()
    return seeded


mce.auto_widgets = auto
display.SMProxy.GetProperty("GaussianWidgets").AddObserver("ModifiedEvent", record)
display.SMProxy.GetProperty("GaussianWidgetsHidden").AddObserver("ModifiedEvent", record_hidden)
save()
