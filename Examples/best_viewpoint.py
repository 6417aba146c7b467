"""Best and worst viewpoints of a volume, as images: the best-viewpoint capability alone.

    xvfb-run -a pvbatch Examples/best_viewpoint.py [VOLUME] [OUTPUT_DIR | --output DIR]
        [--size W H] [--plugin PATH]

VOLUME      a volume ParaView can read as image data (default: Colin27 ch2.nii.gz from
            the project's data folder, .cache/volumes). .nii/.nii.gz and VolPack .den are
            read by the plugin's readers.
OUTPUT_DIR  where the images go (default: output/best_viewpoint; --output DIR says the same).
--plugin    the MultichannelExplorer plugin library (default: $MCV_PLUGIN, then
            PV_PLUGIN_PATH, then the build folders of this repository).

The volume's opacity: 0 up to Otsu's threshold of its histogram (the background), then a
ramp to 1 at its maximum; a volume of several components per voxel (a 4D NIfTI file read
with TimeAsVector, e.g. diffusion MRI) is shown and analysed by its magnitude. Writes
best.png (camera along v3, the direction of least variance of the 3D Harris interest
points), worst.png (along v1), best_points.png (best view with the interest points over the
volume, drawn fainter) and best_viewpoint.json; prints the directions and eigenvalues. A
picture that comes out empty ends the script with an error (and no best_viewpoint.json).
"""
import json
import os
import sys
import time

from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from example_support import DATA, argument_parser, load_plugin, render_view, require  # noqa: E402


parser = argument_parser(__doc__)
parser.add_argument("volume", nargs="?", default=os.path.join(DATA, "ch2.nii.gz"),
                    help="a volume ParaView reads as image data")
parser.add_argument("output", nargs="?", default=os.path.join("output", "best_viewpoint"),
                    help="where the images go")
parser.add_argument("--output", dest="output_option", metavar="DIR",
                    help="where the images go (as OUTPUT_DIR, the other examples' spelling)")
parser.add_argument("--plugin", default=None,
                    help="the MultichannelExplorer plugin library (none: $MCV_PLUGIN, then "
                         "PV_PLUGIN_PATH, then build*/ of this repository)")
parser.add_argument("--size", type=int, nargs=2, default=[800, 600], metavar=("W", "H"),
                    help="the pictures' size in pixels")
args = parser.parse_args(sys.argv[1:])
args.output = args.output_option or args.output

require(args.volume)
os.makedirs(args.output, exist_ok=True)

# 1. The plugin: the BestViewpoint filter, the readers and the Python module.
mce = load_plugin(args.plugin)

# 2. The volume, shown as a volume: the opacity transfer function of this display is the
#    one the best viewpoint is computed from.
volume = OpenDataFile(args.volume)
if volume is None:
    sys.exit("ParaView found no reader for %s" % args.volume)
volume.UpdatePipeline()
info = volume.GetDataInformation()
array = volume.PointData.keys()[0]
print("volume   %s: %s, extent %s, array '%s' range %s" % (
    args.volume, volume.GetXMLLabel(), info.GetExtent(), array,
    volume.PointData[array].GetRange()))
components = volume.PointData[array].GetNumberOfComponents()
if components > 1:
    # ParaView draws a vector array by its magnitude; the opacity the best view is found
    # for must be that of the picture, so both take the magnitude as one array.
    volume = PythonCalculator(Input=volume, ArrayName=array + "_magnitude", Expression=(
        "numpy.sqrt(numpy.sum(numpy.square(inputs[0].PointData[%r].astype(numpy.float64)), "
        "axis=1))" % array))
    volume.UpdatePipeline()
    array = array + "_magnitude"
    print("         %d components per voxel: shown and analysed by their magnitude '%s', "
          "range %s" % (components, array, volume.PointData[array].GetRange()))



def otsu_threshold(source, name, bins=256):
    """Otsu's threshold of point array `name`: the value that best splits its histogram in
    two classes (background, tissue). The histogram is ParaView's Histogram filter's, so
    it is computed where the data is (every process's piece under MPI). Written here: VTK
    and ParaView have no Otsu filter (ITK's is not a dependency)."""
    histogram = Histogram(Input=source, SelectInputArray=["POINTS", name], BinCount=bins)
    table = servermanager.Fetch(histogram)
    counts = table.GetRowData().GetArray("bin_values")
    extents = table.GetRowData().GetArray("bin_extents")
    n = [counts.GetValue(i) for i in range(counts.GetNumberOfTuples())]
    x = [extents.GetValue(i) for i in range(extents.GetNumberOfTuples())]
    Delete(histogram)
    total, weighted = float(sum(n)), sum(c * v for c, v in zip(n, x))
    best, threshold, below, below_sum = -1.0, x[0], 0.0, 0.0
    for c, v in zip(n[:-1], x[:-1]):
        below += c
        below_sum += c * v
        above = total - below
        if below and above:
            between = below * above * (below_sum / below - (weighted - below_sum) / above) ** 2
            if between > best:
                best, threshold = between, v
    return threshold


view = render_view(args.size)
display = Show(volume, view)
display.SetRepresentationType("Volume")
ColorBy(display, ("POINTS", array))
display.RescaleTransferFunctionToDataRange(True, False)
GetColorTransferFunction(array).ApplyPreset("Grayscale", True)
# Opacity 0 up to Otsu's threshold, then a ramp to 1: the background (scanner noise around
# the head) draws nothing, where ParaView's default ramp from the minimum would fill the
# grid's box with a haze, and the best view and its framing would count that haze as
# something to show.
low, high = volume.PointData[array].GetRange()
threshold = otsu_threshold(volume, array)
GetOpacityTransferFunction(array).Points = [low, 0.0, 0.5, 0.0, threshold, 0.0, 0.5, 0.0,
                                            high, 1.0, 0.5, 0.0]
print("opacity  0 up to %.4g (Otsu's threshold), a ramp to 1 at %.4g" % (threshold, high))

# 3. Best view: camera along v3, the side of higher image entropy (disambiguate=True).
start = time.time()
best = mce.apply_best_viewpoint(volume, view, which="best", disambiguate=True)
elapsed = time.time() - start
if not best.valid:
    sys.exit("no best viewpoint for this volume (flat or constant opacity)")
SaveScreenshot(os.path.join(args.output, "best.png"), view)

# ... with the interest points over the volume (orange spheres; colour them by the
# HarrisScore array to see the response strength). Most of them lie inside the volume, so
# it is drawn ten times fainter for this picture (its opacity unit distance x10).
points = Show(best.filter, view)
points.SetRepresentationType("Points")
ColorBy(points, None)
points.AmbientColor = points.DiffuseColor = [1.0, 0.45, 0.1]
points.PointSize = 5
points.RenderPointsAsSpheres = 1
unit_distance = display.ScalarOpacityUnitDistance
display.ScalarOpacityUnitDistance = 10 * unit_distance
Render(view)
SaveScreenshot(os.path.join(args.output, "best_points.png"), view)
display.ScalarOpacityUnitDistance = unit_distance
Hide(best.filter, view)

# 4. Worst view: camera along v1 (most variance: structures hide each other).
worst = mce.apply_best_viewpoint(volume, view, which="worst", disambiguate=True)
SaveScreenshot(os.path.join(args.output, "worst.png"), view)

# 5. Report (an error when a picture came out empty).
for name in ("best", "best_points", "worst"):
    drawn = mce.image_statistics(os.path.join(args.output, name + ".png"))
    if not drawn["non_background_fraction"] > 0.02:  # the orientation axes alone: ~0.5 %
        sys.exit("%s.png: nothing drawn (%.1f %% of the pixels)"
                 % (name, 100 * drawn["non_background_fraction"]))
bvp = best.filter
timings = [float(x) for x in bvp.GetPropertyValue("StageTimings")]
eig = best.eigenvalues
summary = {
    "volume": os.path.abspath(args.volume),
    "best_direction": best.direction,
    "worst_direction": worst.direction,
    "view_up": best.view_up,
    "eigenvalues": eig,
    "entropy_bits": {"best": best.entropies, "worst": worst.entropies},
    "interest_points": bvp.GetDataInformation().GetNumberOfPoints(),
    "device": best.device,
    "stage_ms": dict(zip(("harris", "select", "pca", "total"), timings)),
    "images": {k: os.path.abspath(os.path.join(args.output, k + ".png"))
               for k in ("best", "best_points", "worst")},
}
with open(os.path.join(args.output, "best_viewpoint.json"), "w") as f:
    json.dump(summary, f, indent=2)

fmt = lambda v: "(%+.4f, %+.4f, %+.4f)" % tuple(v)  # noqa: E731
print("best     direction %s  (camera looks along it; view-up %s)" % (
    fmt(best.direction), fmt(best.view_up)))
print("worst    direction %s" % fmt(worst.direction))
print("eigenvalues        %.4f %.4f %.4f  (normalised; v3 holds %.1f%% of the spread)" % (
    eig[0], eig[1], eig[2], 100 * eig[2]))
print("interest points    %d on %s; Harris %.1f ms, top-N %.1f ms, PCA %.2f ms, "
      "total %.1f ms (apply_best_viewpoint with disambiguation: %.2f s)" % (
          summary["interest_points"], best.device, timings[0], timings[1], timings[2],
          timings[3], elapsed))
print("images             %s" % ", ".join(sorted(summary["images"].values())))
