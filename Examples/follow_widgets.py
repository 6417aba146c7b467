"""The camera follows the transfer function: the best view of each structure in turn.

    xvfb-run -a pvbatch Examples/follow_widgets.py [--output DIR]

Colin27 T1 + AAL + Brodmann -> 6D features -> PCA domain -> 3 widgets seeded at k-means
clusters. follow_best_viewpoint() then keeps the camera on the best view of whatever the
widgets show: switching to one widget at a time turns the camera (in a few rendered
steps) to that structure's best view. Writes widget<i>.png and prints the directions.
"""
import os
import sys

from paraview import simple
from paraview.simple import *  # noqa: F401,F403

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from example_support import (DATA, add_output_options, argument_parser,  # noqa: E402
                             load_plugin, render_view, require)

parser = argument_parser(__doc__)
add_output_options(parser, os.path.join("output", "follow_widgets"), (500, 400))
args = parser.parse_args(sys.argv[1:])
paths = [require(os.path.join(DATA, n)) for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
os.makedirs(args.output, exist_ok=True)
mce = load_plugin(args.plugin)

# 1. Three channels -> 6D feature vectors -> a 3D domain (PCA: the quickest reduction).
volume = simple.MergeChannels(Input=[OpenDataFile(p) for p in paths])
features, reduction = mce.reduce_multichannel(volume, method="PCA", features="6D",
                                              ReferenceSampleSize=5000)

# 2. The volume through Gaussian widgets seeded at the domain's clusters.
view = render_view(args.size)
display = mce.show_gaussian_tf(reduction, view, blend="Maximum Intensity")
widgets = mce.auto_widgets(display, 3, opacity=0.8)

# 3. From now on every change of display.GaussianWidgets turns the camera.
follower = mce.follow_best_viewpoint(display, view, frames=6)
for i in range(0, len(widgets), 8):
    display.GaussianWidgets = widgets[i:i + 8]  # one structure at a time
    result = follower.state["result"]
    if result is None:
        sys.exit("no best view for widget %d" % (i // 8))
    direction = tuple(result.direction)
    follower.state["result"] = None
    print("widget %d (colour %.2f %.2f %.2f): best view (%+.3f, %+.3f, %+.3f)"
          % ((i // 8,) + tuple(widgets[i + 4:i + 7]) + direction))
    SaveScreenshot(os.path.join(args.output, "widget%d.png" % (i // 8)), view)
follower.stop()
print("output: %s" % os.path.abspath(args.output))
