"""GUI test of the Gaussian widget editor's Save... and Load... buttons (transfer-function
files, .mcvtf), part 1 (run by `paraview --script=` before gui_tffile_click.xml clicks).
The real brain (Colin27 T1 + AAL, every 4th voxel, written as a .vti) reduced by PCA, shown
as a Gaussian TF Volume with two widgets; every change of GaussianWidgets and of the
reduction's ModelFile is recorded into $MCV_GUI_STATE for gui_tffile_check.py. The click
script saves to $MCV_OUTPUT_DIR/gui_tffile/saved.mcvtf (--test-directory is
$MCV_OUTPUT_DIR), adds a widget, loads the file, then undoes the load. After the load a
screenshot of the screen goes to $MCV_OUTPUT_DIR/gui_tffile/screen.png (or to
$MCV_TFFILE_SCREENSHOT, for the docs' picture)."""
import json
import os
import shutil
import subprocess

from paraview.simple import *  # noqa: F401,F403,E402
import multichannel_explorer as mce  # noqa: E402
import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter  # noqa: E402

out = os.path.join(os.environ.get("MCV_OUTPUT_DIR", "."), "gui_tffile")
if os.path.isdir(out):
    shutil.rmtree(out)
os.makedirs(out)
state_file = os.environ.get("MCV_GUI_STATE") or os.path.join(out, "state.json")
screenshot = os.environ.get("MCV_TFFILE_SCREENSHOT") or os.path.join(out, "screen.png")

channels = []
for name in ("ch2", "aal"):  # as mcv_testing.brain_arrays (no __file__ in --script)
    reader = NIfTIImageReader(FileName=os.path.join(os.environ["MCV_DATA_DIR"],
                                                    name + ".nii.gz"))
    data = servermanager.Fetch(reader)
    nx, ny, nz = data.GetDimensions()
    values = vtk_to_numpy(data.GetPointData().GetArray(0)).reshape(nz, ny, nx)
    channels.append(np.ascontiguousarray(values[::4, ::4, ::4], dtype=np.float32))
    Delete(reader)
brain = np.stack(channels)
image = vtkImageData()
image.SetDimensions(brain.shape[3], brain.shape[2], brain.shape[1])
image.SetSpacing(4.0, 4.0, 4.0)
for name, values in (("ch2", brain[0]), ("aal", brain[1])):
    array = numpy_to_vtk(values.ravel(), deep=1)
    array.SetName(name)
    image.GetPointData().AddArray(array)
volume_path = os.path.join(out, "brain.vti")
writer = vtkXMLImageDataWriter()
writer.SetFileName(volume_path)
writer.SetInputData(image)
writer.Write()

volume = OpenDataFile(volume_path)
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
ResetCamera(view)
Render(view)
SetActiveSource(reduction)  # the Properties panel shows its display: the editor

state = {"initial": WIDGETS, "events": [], "folder": out}


def save():
    with open(state_file, "w") as f:
        json.dump(state, f, indent=1)


SCREENSHOT = """
window=$(xdotool search --onlyvisible --name ParaView 2>/dev/null | head -n 1)
if [ -n "$window" ]; then
  xdotool windowmove "$window" 0 0 windowsize "$window" 1600 1000
  sleep 1
  xdotool mousemove 294 300 sleep 0.3 mousedown 1 sleep 0.3 mousemove 320 300 sleep 0.3 \\
    mousemove 400 300 sleep 0.3 mousemove 470 300 sleep 0.3 mouseup 1
  sleep 1
  # The splitter under the Pipeline Browser up: the editor's buttons in view.
  xdotool mousemove %s sleep 0.3 mousedown 1 sleep 0.3 mousemove %s sleep 0.3 \\
    mouseup 1
  sleep 2
fi
xwd -root -silent | convert xwd:- '%s'
"""


SPLITTER_FROM = os.environ.get("MCV_SPLITTER_FROM", "230 434")
SPLITTER_TO = os.environ.get("MCV_SPLITTER_TO", "230 200")


def record(kind):
    def on_change(*unused):
        if kind == "widgets":
            value = [float(v) for v in display.GaussianWidgets]
        else:
            value = str(reduction.ModelFile)
        state["events"].append([kind, value])
        save()
        if kind == "model" and value and not state.get("screenshot"):
            state["screenshot"] = screenshot
            # In the background: the GUI repaints while the click script waits.
            subprocess.Popen("sleep 1;" + SCREENSHOT % (SPLITTER_FROM, SPLITTER_TO, screenshot),
                             shell=True)
    return on_change


display.SMProxy.GetProperty("GaussianWidgets").AddObserver("ModifiedEvent", record("widgets"))
reduction.SMProxy.GetProperty("ModelFile").AddObserver("ModifiedEvent", record("model"))
save()
