"""GUI test of the Gaussian widget editor's Save... and Load... buttons (transfer-function
files, .mcvtf), part 1 (run by `paraview --script=` before gui_tffile_click.xml clicks).
The real brain (Colin27 T1 + AAL, every 4th voxel, written as a .vti) reduced by PCA, shown
as a Gaussian TF Volume with two widgets; every change of GaussianWidgets and of the
reduction's ModelFile is recorded into $MCV_GUI_STATE for gui_tffile_check.py. The click
script saves to $MCV_OUTPUT_DIR/gui_tffile/saved.mcvtf (--test-directory is
$MCV_OUTPUT_DIR), adds a widget, loads the file, then undoes the load. After the load a
screenshot of the screen goes to $MCV_OUTPUT_DIR/gui_tffile/screen.png (or to
$MCV_GUI_SCREENSHOT, for the docs' picture)."""
import os

from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

import gui_setup as G
import mcv_testing as T

out = T.fresh_output_dir("gui_tffile")
screenshot = os.environ.get("MCV_GUI_SCREENSHOT") or os.path.join(out, "screen.png")

brain = T.brain_arrays(("ch2", "aal"), step=4)
volume = OpenDataFile(T.write_vti(os.path.join(out, "brain.vti"),
                                  [("ch2", brain[0]), ("aal", brain[1])], (4.0, 4.0, 4.0)))
_, reduction = mce.reduce_multichannel(volume, "PCA", "6D", ReferenceSampleSize=2000)
RenameSource("Reduction", reduction)
reduction.UpdatePipeline()
coords = vtk_to_numpy(servermanager.Fetch(reduction).GetPointData().GetArray(
    "ReducedCoordinates"))
size = float((coords.max(axis=0) - coords.min(axis=0)).max())
WIDGETS = []
for q, colour in ((0.3, (1.0, 0.2, 0.1)), (0.7, (0.1, 0.5, 1.0))):
    WIDGETS += [float(v) for v in np.quantile(coords, q, axis=0)] + [0.08 * size] + \
        list(colour) + [0.8]
view = GetActiveViewOrCreate("RenderView")
display = mce.show_gaussian_tf(reduction, view, widgets=WIDGETS)
NAMES = ["grey matter", "white matter"]
display.GaussianWidgetNames = NAMES
ResetCamera(view)
Render(view)
SetActiveSource(reduction)  # the Properties panel shows its display: the editor

state = G.State("tffile", in_folder=out, initial=WIDGETS, initial_names=NAMES, events=[],
                names_at_widgets=[], folder=out)
save = state.save
# The splitter under the Pipeline Browser moved up in the screenshot: the editor's buttons
# in view.
SPLITTER_FROM = os.environ.get("MCV_SPLITTER_FROM", "230 434")
SPLITTER_TO = os.environ.get("MCV_SPLITTER_TO", "230 200")


def record(kind):
    def on_change(*unused):
        if kind == "widgets":
            value = [float(v) for v in display.GaussianWidgets]
            state["names_at_widgets"].append(
                [str(v) for v in display.GetProperty("GaussianWidgetNames")])
        else:
            value = str(reduction.ModelFile)
        state["events"].append([kind, value])
        save()
        if kind == "model" and value and not state.get("screenshot"):
            state["screenshot"] = screenshot
            G.screenshot(screenshot, delay=1, place_window=True,
                         drags=[(SPLITTER_FROM, SPLITTER_TO)])
    return on_change


display.SMProxy.GetProperty("GaussianWidgets").AddObserver("ModifiedEvent", record("widgets"))
reduction.SMProxy.GetProperty("ModelFile").AddObserver("ModifiedEvent", record("model"))
save()
