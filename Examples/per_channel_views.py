"""Best views of each channel of a multichannel volume, and of all channels together.

    xvfb-run -a pvbatch Examples/per_channel_views.py [--output DIR] [--channels V1 V2 ...]

Default: the Colin27 T1 (ch2) with the AAL and Brodmann atlases (mricron-data), three
volumes on one grid. Each channel gets its own best viewpoint (its own range mapped
linearly to opacity), then all of them together (opacity = the maximum over channels).
Writes <channel>.png per channel (named after its point array, as MergeChannels names the
channels, characters other than letters, digits, '.', '-' and '_' replaced by '_'), all.png
(the array all_channels: at each voxel the maximum over channels of each one's value scaled
from its range to 0..1, the opacity that view was found for), each picture titled with
what it shows, and report.json (each picture's channels, colouring array and best
direction), and prints each direction and its angle to the all-channel one: channels that
show different structures prefer different views.
"""
import json
import math
import os
import re
import sys

from paraview import simple
from paraview.simple import *  # noqa: F401,F403

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from example_support import (DATA, add_output_options, argument_parser,  # noqa: E402
                             load_plugin, render_view, require)

parser = argument_parser(__doc__)
parser.add_argument("--channels", nargs="+", metavar="VOLUME",
                    default=[os.path.join(DATA, n) for n in
                             ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")],
                    help="volumes on one grid, one channel each")
add_output_options(parser, os.path.join("output", "per_channel_views"), (500, 400))
args = parser.parse_args(sys.argv[1:])
for path in args.channels:
    require(path)
os.makedirs(args.output, exist_ok=True)
mce = load_plugin(args.plugin)

# The channels on one grid: one point array each.
volume = simple.MergeChannels(Input=[OpenDataFile(p) for p in args.channels])
volume.UpdatePipeline()
# One array per channel, named by MergeChannels (not in the order of the files: the
# pictures are named after the arrays they show).
names = volume.PointData.keys()

view = render_view(args.size)


# All channels in one picture: at each voxel the maximum over channels of each one's value
# scaled from its range to 0..1, which is the opacity the all-channel view is found for.
scaled = ["(inputs[0].PointData['%s'] - %r) / %r" % (n, lo, max(hi - lo, 1e-30))
          for n in names for lo, hi in [volume.PointData[n].GetRange()]]
combined = simple.PythonCalculator(Input=volume, ArrayName="all_channels",
                                   Expression="numpy.maximum.reduce([%s])" % ", ".join(scaled))
combined.UpdatePipeline()
title = simple.Text(Text="")
title_display = Show(title, view)
title_display.WindowLocation = "Upper Center"
title_display.FontSize = 14


def best_view_of(channels, image, source=volume, array=None):
    """Shows `array` of `source` (default: the first channel) as the volume and turns the
    camera to the best view of `channels` (explicit Channels: the filter does not follow
    the display's colouring)."""
    shown = Show(source, view)
    shown.SetRepresentationType("Volume")
    for other in {volume, combined} - {source}:
        Hide(other, view)
    ColorBy(shown, ("POINTS", array or channels[0]))
    shown.RescaleTransferFunctionToDataRange(True, False)
    result = mce.apply_best_viewpoint(volume, view, Channels=list(channels), OpacityFunction=None)
    if not result.valid:
        sys.exit("no best view for %s" % ", ".join(channels))
    title.Text = ("%s: best view of %s" % (array, " + ".join(channels)) if array else
                  "%s: its best view" % channels[0])
    SaveScreenshot(os.path.join(args.output, image), view)
    views.append(dict(image=image, channels=list(channels), coloured_by=shown.ColorArrayName[1],
                      direction=[float(d) for d in result.direction]))
    return result


views = []
everything = best_view_of(names, "all.png", combined, "all_channels")
print("%-12s %-28s %s" % ("channels", "best direction", "angle to all-channel view"))
for name in names:
    result = best_view_of([name], "%s.png" % re.sub(r"[^A-Za-z0-9_.-]+", "_", name))
    cosine = abs(sum(a * b for a, b in zip(result.direction, everything.direction)))
    print("%-12s (%+.3f, %+.3f, %+.3f)   %5.1f deg" % (
        (name,) + tuple(result.direction) + (math.degrees(math.acos(min(1.0, cosine))),)))
print("%-12s (%+.3f, %+.3f, %+.3f)" % (("all",) + tuple(everything.direction)))
with open(os.path.join(args.output, "report.json"), "w") as f:
    json.dump(views, f, indent=1)
print("output: %s" % os.path.abspath(args.output))
