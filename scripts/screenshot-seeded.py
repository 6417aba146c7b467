"""The seeded brain and its reduced domain, as a new user gets them (pvbatch):

    MCV_PLUGIN=build/lib/paraview-5.11/plugins/MultichannelExplorer/MultichannelExplorer.so \
        xvfb-run -a pvbatch scripts/screenshot-seeded.py [OUTPUT_FOLDER]

Colin27 T1 + AAL + Brodmann (.cache/volumes, or MCV_DATA_DIR) -> MergeChannels ->
MultichannelFeatures -> DimensionReduction (defaults) -> "Gaussian TF Volume" with 4
widgets seeded (auto_widgets, as the toolbar's Seed Gaussian Widgets), turned to the best
viewpoint of the widgets' opacity, the reduced domain beside it (show_dual_domain).
Writes seeded_brain.png (the volume with its widget legend) and seeded_domain.png (the
domain view) into OUTPUT_FOLDER (default docs/images), and prints the widgets.
"""
import os
import sys

from paraview import simple

here = os.path.dirname(os.path.abspath(__file__))
repo = os.path.dirname(here)
plugin = os.environ.get("MCV_PLUGIN") or os.path.join(
    repo, "build", "lib", "paraview-5.11", "plugins", "MultichannelExplorer",
    "MultichannelExplorer.so")
simple.LoadPlugin(plugin, remote=False)
import multichannel_explorer as mce  # noqa: E402

data = os.environ.get("MCV_DATA_DIR") or os.path.join(repo, ".cache", "volumes")
out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(repo, "docs", "images")
os.makedirs(out, exist_ok=True)

readers = [simple.OpenDataFile(os.path.join(data, f))
           for f in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
merged = simple.MergeChannels(Input=readers)
features = simple.MultichannelFeatures(Input=merged)
reduction = simple.DimensionReduction(Input=features)
view = simple.CreateRenderView()
view.ViewSize = [640, 560]
view.OrientationAxesVisibility = 0
display = mce.show_gaussian_tf(reduction, view)
widgets = mce.auto_widgets(display, 4)
mce.apply_best_viewpoint(reduction, view)  # the widgets' opacity (the main job's call)
simple.Render(view)
dual = mce.show_dual_domain(display, view)
dual.domain_view.ViewSize = [560, 560]
dual.domain_view.OrientationAxesVisibility = 1
simple.Render(dual.domain_view)
display.UpdatePropertyInformation()
print("names:", list(display.GaussianWidgetNames))
print("hidden:", list(display.GaussianWidgetsHidden))
print("legend:\n" + display.GetProperty("GaussianWidgetLegend").GetElement(0))
for w in range(len(widgets) // 8):
    print("widget %d: %s" % (w + 1, ["%.4g" % v for v in display.GaussianWidgets[8 * w:8 * w + 8]]))
simple.SaveScreenshot(os.path.join(out, "seeded_brain.png"), view, ImageResolution=[640, 560])
simple.SaveScreenshot(os.path.join(out, "seeded_domain.png"), dual.domain_view,
                      ImageResolution=[560, 560])
print("wrote", os.path.join(out, "seeded_brain.png"), os.path.join(out, "seeded_domain.png"))
sys.stdout.flush()
os._exit(0)
