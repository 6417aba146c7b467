"""The README's picture of the whole loop in the ParaView GUI (run by
scripts/screenshot-gui.sh through `paraview --script=`): the real 3-channel brain, its
channels merged as the README does (MergeChannels, MultichannelFeatures 6D ->
DimensionReduction Isomap), as a Gaussian TF Volume with 4 seeded widgets, its reduced
domain beside it (the widgets as draggable spheres), the widget editor in the Properties
panel, the camera at the best view, one voxel probed. Writes the file $MCV_GUI_DONE, when
set, once everything is shown."""
import os

from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mx

data = os.environ.get("MCV_DATA_DIR", os.path.join(os.getcwd(), ".cache", "volumes"))
channels = [OpenDataFile(os.path.join(data, name))
            for name in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
volume = MergeChannels(Input=channels)  # noqa: F405 (the plugin, auto-loaded)
features, reduction = mx.reduce_multichannel(volume, "Isomap", "6D")
view = GetActiveViewOrCreate("RenderView")
display = mx.show_gaussian_tf(reduction, view)
mx.auto_widgets(display, 4)
dual = mx.show_dual_domain(display, view)
mx.apply_best_viewpoint(reduction, view)
mx.probe(display, (90, 108, 90))
SetActiveView(view)
SetActiveSource(reduction)
Render(dual.domain_view)
Render(view)
if os.environ.get("MCV_GUI_DONE"):
    with open(os.environ["MCV_GUI_DONE"], "w") as f:
        f.write("done\n")
