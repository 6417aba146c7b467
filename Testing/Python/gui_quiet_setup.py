"""GUI test "no noise for the expected case", part 1 (run by `paraview --script=`): with
Device Auto everywhere (the default) and whatever GPU this machine has, the whole chain on
the real 3-channel brain (MultichannelFeatures -> DimensionReduction -> Gaussian TF
Volume, per voxel and per sample -> seeded widgets -> best viewpoint) runs in the GUI.
Every warning and error that reaches ParaView's output window (what opens the Output
Messages window) is recorded into $MCV_GUI_STATE; gui_quiet_check.py wants none."""
import os

from paraview.simple import *  # noqa: F401,F403
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow
import multichannel_explorer as mce
import gui_setup as G

out = G.output_dir()
state = G.State("quiet", messages=[], steps=[])
save = state.save


@calldata_type(VTK_STRING)
def record(caller, event, text):
    state["messages"].append("%s: %s" % (event, text))
    save()


window = vtkOutputWindow.GetInstance()
state["output_window"] = window.GetClassName()
for event in (vtkCommand.WarningEvent, vtkCommand.ErrorEvent):
    window.AddObserver(event, record)
save()

volume = AppendAttributes(Input=[OpenDataFile(G.data_path(n))
                                 for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")])
features, reduction = mce.reduce_multichannel(volume, "PCA", "6D")
state["steps"].append("reduced on " + str(reduction.GetPropertyValue("DeviceUsed")))
view = GetActiveViewOrCreate("RenderView")
for classification in ("Per voxel", "Per sample"):
    display = mce.show_gaussian_tf(reduction, view, classification=classification)
    mce.auto_widgets(display, 3)
    ResetCamera(view)
    Render(view)
    display.UpdatePropertyInformation()
    state["steps"].append("%s on %s" % (classification, display.GetPropertyValue("GaussianTFDeviceUsed")))
result = mce.apply_best_viewpoint(reduction, view)
state["steps"].append("best viewpoint on %s, valid %s" % (result.device, result.valid))
state["done"] = True
save()
SaveScreenshot(os.path.join(out, "gui_quiet.png"), view)
