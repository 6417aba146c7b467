"""GUI test of the Gaussian widget editor (the GaussianWidgets rows of the Properties
panel), part 1 (run by `paraview --script=` before gui_editor_click.xml edits the widgets).
A synthetic volume whose ReducedCoordinates are the voxel positions (-20..20 on each
axis) is shown as a Gaussian TF Volume with one widget; every change of GaussianWidgets
and of GaussianWidgetsHidden is recorded into $MCV_GUI_STATE for gui_editor_check.py.
After the last edit a screenshot of the whole screen goes to $MCV_OUTPUT_DIR (or to
$MCV_GUI_SCREENSHOT, for the picture in docs/gui.md)."""
import os

from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce
import gui_setup as G

screenshot = (os.environ.get("MCV_GUI_SCREENSHOT") or
              os.path.join(G.output_dir(), "gui_editor.png"))
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

state = G.State("editor", states=[], hidden=[])
save = state.save


def record(*unused):
    state["states"].append([float(v) for v in display.GaussianWidgets])
    save()
    if len(state["states"]) == EDITS:
        G.screenshot(screenshot, delay=1, place_window=True)


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
