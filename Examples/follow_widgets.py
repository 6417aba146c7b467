"""The camera follows the transfer function: the best view of each structure in turn.

    xvfb-run -a pvbatch Examples/follow_widgets.py [--output DIR]

Colin27 T1 + AAL + Brodmann -> 6D features -> PCA domain -> 4 widgets seeded at k-means
clusters (the one of most voxels hidden). follow_best_viewpoint() then keeps the camera on
the best view of whatever the widgets show: showing one widget at a time (show_widgets, the
others hidden) turns the camera (in a few rendered steps) to that structure's best view,
centred on it. Writes widget<i>.png for each widget shown by the seeding (an error when one
is empty) and prints the directions.
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
display = mce.show_gaussian_tf(reduction, view)
widgets = mce.auto_widgets(display, 4, opacity=0.8)  # the class of most voxels starts hidden

# 3. The camera fitted to the best view of all of them, then, from now on, every change of
#    display.GaussianWidgets turns it to the best view of what the widgets show.
mce.apply_best_viewpoint(reduction, view)
follower = mce.follow_best_viewpoint(display, view, frames=6)
names = list(display.GaussianWidgetNames)
for i, name in enumerate(names):
    if not widgets[8 * i + 7] > 0:
        continue  # hidden by the seeding: the background-sized class, no structure
    mce.show_widgets(display, [i])  # one structure at a time, the others hidden
    result = follower.state["result"]
    if result is None:
        sys.exit("no best view for widget %d (%s)" % (i, name))
    follower.state["result"] = None
    print("widget %d, %s (colour %.2f %.2f %.2f): best view (%+.3f, %+.3f, %+.3f)"
          % ((i, name) + tuple(widgets[8 * i + 4:8 * i + 7]) + tuple(result.direction)))
    picture = os.path.join(args.output, "widget%d.png" % i)
    SaveScreenshot(picture, view)
    drawn = mce.image_statistics(picture)["non_background_fraction"]
    if not drawn > 0.02:  # the orientation axes alone cover ~0.5 %
        sys.exit("%s: nothing drawn (%.1f %% of the pixels)" % (picture, 100 * drawn))
follower.stop()
print("output: %s" % os.path.abspath(args.output))
