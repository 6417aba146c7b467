"""The whole method on a multichannel volume: the suite's main job.

    xvfb-run -a pvbatch Examples/transfer_function.py [--output DIR] [options]

Default input: the real 3-channel brain of Debian's mricron-data (Colin27 T1 ch2 + the
AAL and Brodmann atlases on the same grid), fetched by scripts/fetch-data.sh. Your own
data: --channels A B C (one file per channel, on one grid) or --input FILE (one multichannel
file: an ImageJ hyperstack, an OME-TIFF, an OME-Zarr folder; its channels are its arrays).

 0. with --upsample F, the channels resampled by F along each axis (ParaView's own
    trilinear ResampleToImage): the same brain as a larger volume (F = 2: 57 M voxels);
 1. per-voxel feature vectors (24D by default), 2. reduced to 3D (landmark Isomap fitted
    on a reference sample, every voxel placed out of sample): by default in one
    DimensionReduction on the channels (--chain fused: the features are computed a slab
    at a time and never stored); --chain features runs MultichannelFeatures ->
    DimensionReduction (the Features array in memory, 96 bytes per voxel at 24D);
 3. Gaussian widgets seeded at the k-means clusters of the reduced domain (auto_widgets);
 4. the volume rendered through those widgets ("Gaussian TF Volume" representation);
 5. the best viewpoint of what the widgets show (3D Harris + PCA of the widget opacity);
writes into the output folder best.png, worst.png, dual_domain.png (volume and reduced
domain side by side), domain.png, spectrum.png (bar chart of the leading eigenvalues, the
kept ones highlighted, the variance retained in the title), methods.png (the reduced
domains of PCA, Isomap, LLE and UMAP side by side, see --no-methods) and report.json (timings
and peak resident memory per stage, variance retained, trustworthiness, view directions,
eigenvalues, the figures),
then prints a summary and the folder.

--method UMAP reduces with UMAP instead (K = --umap-neighbors, 15).

methods.png: the four methods are fitted on the same reference sample (same size, K, L
and seed; UMAP with its own K) of a coarser grid, every --methods-stride-th voxel per axis of the features
(placing all voxels four more times would cost more than the whole job); the same
--methods-sample voxels are drawn in each, coloured by the main domain's widgets.
"""
import argparse
import json
import os
import resource
import sys
import time

from paraview import servermanager, simple
from paraview.simple import *  # noqa: F401,F403

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from example_support import DATA, load_plugin, render_view, require  # noqa: E402
import report_figures  # noqa: E402

parser = argparse.ArgumentParser(
    description=__doc__.split("\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter,
    epilog=__doc__.split("\n", 2)[2])
parser.add_argument("--channels", nargs="+", metavar="VOLUME",
                    default=[os.path.join(DATA, n) for n in
                             ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")],
                    help="volumes on one grid, one channel each (default: Colin27 T1, "
                         "AAL, Brodmann)")
parser.add_argument("--input", metavar="FILE", default=None,
                    help="one multichannel file instead of --channels: an ImageJ hyperstack "
                         "or OME-TIFF (.tif, .ome.tif), an OME-Zarr folder (.zarr), or any "
                         "volume ParaView opens; its point arrays are the channels, its first "
                         "time step is used")
parser.add_argument("--output", default=os.path.join("output", "transfer_function"))
parser.add_argument("--features", default="24D", choices=["6D", "24D"])
parser.add_argument("--chain", default="fused", choices=["fused", "features"],
                    help="fused: DimensionReduction on the channels (default); features: "
                         "MultichannelFeatures -> DimensionReduction")
parser.add_argument("--upsample", type=float, default=1.0, metavar="F",
                    help="resample the channels by F along each axis first (trilinear)")
parser.add_argument("--method", default="Isomap", choices=["PCA", "Isomap", "LLE", "UMAP"])
parser.add_argument("--reference-size", type=int, default=10000,
                    help="voxels the embedding is fitted on (default 10000)")
parser.add_argument("--neighbors", type=int, default=10, help="K of Isomap/LLE")
parser.add_argument("--umap-neighbors", type=int, default=15,
                    help="K of UMAP (default 15: see DimensionReduction's NumberOfNeighbors)")
parser.add_argument("--landmarks", type=int, default=500, help="L of landmark Isomap")
parser.add_argument("--widgets", type=int, default=4, help="number of seeded widgets")
parser.add_argument("--widget-opacity", type=float, default=0.5)
parser.add_argument("--blend", default="Composite", choices=["Composite", "Maximum Intensity"])
parser.add_argument("--device", default="Auto", choices=["Auto", "CPU", "GPU"])
parser.add_argument("--float16-coordinates", action="store_true",
                    help="store ReducedCoordinates as float16 (half the memory, ~1/2048 "
                         "relative precision; DimensionReduction's CoordinatePrecision)")
parser.add_argument("--seed", type=int, default=0)
parser.add_argument("--size", type=int, nargs=2, default=[800, 600], metavar=("W", "H"))
parser.add_argument("--plugin", default=None, help="MultichannelExplorer.so to load")
parser.add_argument("--no-methods", dest="methods", action="store_false",
                    help="skip methods.png (PCA, Isomap, LLE and UMAP side by side)")
parser.add_argument("--methods-stride", type=int, default=3,
                    help="methods.png: every N-th voxel per axis is reduced (default 3)")
parser.add_argument("--methods-sample", type=int, default=20000,
                    help="methods.png: voxels drawn per method (default 20000)")
args = parser.parse_args(sys.argv[1:])

inputs = [args.input] if args.input else args.channels
for path in inputs:
    require(path)
os.makedirs(args.output, exist_ok=True)
mce = load_plugin(args.plugin)
stages = {}
peak_gib = {}  # the process's peak resident memory at the end of each stage


def peak_rss_gib():
    """Peak resident memory of this process so far (ru_maxrss: KiB on Linux)."""
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0 ** 2, 3)


def _every(n):
    return "every voxel" if n <= 1 else "every %s voxel per axis" % (
        {2: "2nd", 3: "3rd"}.get(n, "%dth" % n))


def timed(name, function):
    start = time.time()
    value = function()
    stages[name] = round(time.time() - start, 3)
    peak_gib[name] = peak_rss_gib()
    print("%-22s %7.2f s   peak RSS %.2f GiB" % (name, stages[name], peak_gib[name]))
    sys.stdout.flush()
    return value


# 1. Channels on one grid, and their feature vectors.
readers = [OpenDataFile(p) for p in inputs]
if None in readers:
    sys.exit("no reader for %s" % inputs[readers.index(None)])
volume = simple.MergeChannels(Input=readers) if len(readers) > 1 else readers[0]
timed("read", volume.UpdatePipeline)
if args.upsample != 1.0:
    # ParaView's own trilinear resampling (vtkProbeFilter) onto a grid F times finer.
    extent = volume.GetDataInformation().GetExtent()
    dims = [extent[2 * a + 1] - extent[2 * a] + 1 for a in range(3)]
    volume = simple.ResampleToImage(
        Input=volume, UseInputBounds=1,
        SamplingDimensions=[max(1, int(round(d * args.upsample))) for d in dims])
    timed("upsample", volume.UpdatePipeline)
if args.chain == "features":
    features = simple.MultichannelFeatures(Input=volume, FeatureSet=args.features,
                                           Device=args.device)
    timed("features", features.UpdatePipeline)
    source, feature_set = features, "Use input array"
else:
    features, source, feature_set = volume, volume, args.features

def neighbors(method):
    return args.umap_neighbors if method == "UMAP" else args.neighbors


# 2. The reduced domain.
precision = "Float16" if args.float16_coordinates else "Float32"
reduction = simple.DimensionReduction(
    Input=source, FeatureSet=feature_set, Method=args.method, OutputDimension=3,
    ReferenceSampleSize=args.reference_size, NumberOfNeighbors=neighbors(args.method),
    NumberOfLandmarks=args.landmarks, RandomSeed=args.seed, Device=args.device,
    CoordinatePrecision=precision)
if args.chain == "features":
    reduction.Features = ["POINTS", "Features"]
timed("reduction", reduction.UpdatePipeline)
reduction.UpdatePropertyInformation()

# 3-4. Widgets seeded in the domain; the volume rendered through them.
view = render_view(args.size)
display = mce.show_gaussian_tf(reduction, view, blend=args.blend)
widgets = timed("seed widgets", lambda: mce.auto_widgets(
    display, args.widgets, opacity=args.widget_opacity, seed=args.seed))
view.ResetCamera()
timed("first render", lambda: Render(view))

# 5. The best viewpoint of the widgets' opacity (the display is a Gaussian TF Volume, so
#    apply_best_viewpoint takes its widgets), and the worst one for comparison.
best = timed("best viewpoint", lambda: mce.apply_best_viewpoint(reduction, view,
                                                                disambiguate=True))
if not best.valid:
    sys.exit("no best viewpoint for these widgets (their opacity is flat or empty)")
SaveScreenshot(os.path.join(args.output, "best.png"), view)


def camera_of(view):
    """What best.png was rendered with: tests re-render the brain's silhouette with it."""
    return {"position": list(view.CameraPosition), "focal_point": list(view.CameraFocalPoint),
            "view_up": list(view.CameraViewUp), "view_angle": float(view.CameraViewAngle),
            "parallel_projection": int(view.CameraParallelProjection),
            "parallel_scale": float(view.CameraParallelScale),
            "size": [int(v) for v in view.ViewSize], "background": list(view.Background)}


best_camera = camera_of(view)
worst = mce.apply_best_viewpoint(reduction, view, which="worst", disambiguate=True)
SaveScreenshot(os.path.join(args.output, "worst.png"), view)
mce.apply_best_viewpoint(reduction, view, disambiguate=True)

# The reduced domain beside the volume, and the eigenvalue spectrum.
dual = timed("dual domain", lambda: mce.show_dual_domain(display, view))
SaveScreenshot(os.path.join(args.output, "dual_domain.png"), dual.layout,
               ImageResolution=[2 * args.size[0], args.size[1]])
SaveScreenshot(os.path.join(args.output, "domain.png"), dual.domain_view)
values, _ = report_figures.spectrum_table(reduction)
variance = float(reduction.GetPropertyValue("VarianceRetained"))
spectrum_bars = report_figures.spectrum_figure(
    os.path.join(args.output, "spectrum.png"), args.method, values, 3, variance)


def coarse(source):
    """Every --methods-stride-th voxel of `source` per axis."""
    rate = max(1, args.methods_stride)
    return simple.ExtractSubset(Input=source, SampleRateI=rate, SampleRateJ=rate,
                                SampleRateK=rate)


def fetch_array(source, name, port=0):
    from vtkmodules.util.numpy_support import vtk_to_numpy

    data = servermanager.Fetch(source, idx=port)
    array = data.GetPointData().GetArray(name)
    # Coordinates may be float16 (--float16-coordinates): decoded to float32.
    return mce.coordinate_values(array) if name == "ReducedCoordinates" else vtk_to_numpy(array)


def reduce_coarse(method, coarse_features):
    """The main reduction's settings (reference size, K, L, seed) with another method, on
    the coarse grid; returns the proxy, updated."""
    other = simple.DimensionReduction(
        Input=coarse_features, FeatureSet=feature_set, Method=method, OutputDimension=3,
        ReferenceSampleSize=args.reference_size, NumberOfNeighbors=neighbors(method),
        NumberOfLandmarks=args.landmarks, RandomSeed=args.seed, Device=args.device,
    CoordinatePrecision=precision)
    if args.chain == "features":
        other.Features = ["POINTS", "Features"]
    other.UpdatePipeline()
    other.UpdatePropertyInformation()
    return other


def method_panels():
    """The same sampled voxels of the coarse grid in the domains of PCA, Isomap, LLE and UMAP,
    each coloured as the main domain's widgets colour it (ReducedDomain's RGBA and
    WidgetOpacity on the main domain's coordinates of those voxels)."""
    coarse_features = coarse(features)
    shown = simple.ReducedDomain(Input=coarse(reduction), SampleSize=args.methods_sample,
                                 RandomSeed=args.seed, GaussianWidgets=widgets)
    shown.Coordinates = ["POINTS", "ReducedCoordinates"]
    voxels = fetch_array(shown, "VoxelId")
    colours = report_figures.point_colours(fetch_array(shown, "RGBA").tolist(),
                                           fetch_array(shown, "WidgetOpacity").tolist())
    panels = []
    for method in ("PCA", "Isomap", "LLE", "UMAP"):
        start = time.time()
        other = reduce_coarse(method, coarse_features)
        xyz = fetch_array(other, "ReducedCoordinates")[voxels]
        panels.append(dict(
            name=method, x=xyz[:, 0].tolist(), y=xyz[:, 1].tolist(), colours=colours,
            variance_retained=float(other.GetPropertyValue("VarianceRetained")),
            trustworthiness=float(other.GetPropertyValue("Trustworthiness")),
            seconds=round(time.time() - start, 3)))
        Delete(other)
    grid = coarse_features.GetDataInformation().GetNumberOfPoints()
    return panels, grid, len(voxels)


methods = None
if args.methods:
    panels, grid, drawn = timed("methods", method_panels)
    caption = ("%s features of %s (%d voxels); each method fitted on the same %d-voxel "
               "reference sample (seed=%d, K=%d, UMAP's K=%d, L=%d); the same %d voxels drawn at "
               "dimensions 1-2, in the colour of the %s domain's widget that selects them "
               "(opacity at least 0.1; the others grey)"
               % (args.features, _every(args.methods_stride), grid, args.reference_size,
                  args.seed, args.neighbors, args.umap_neighbors, args.landmarks, drawn, args.method))
    report_figures.methods_figure(os.path.join(args.output, "methods.png"), panels, caption)
    methods = {p["name"]: {k: p[k] for k in ("variance_retained", "trustworthiness",
                                             "seconds")} for p in panels}
    methods.update(grid_voxels=grid, voxels_drawn=drawn, stride=args.methods_stride)

# Report.
bvp = best.filter
report = {
    "channels": [os.path.abspath(p) for p in inputs],
    "voxels": volume.GetDataInformation().GetNumberOfPoints(),
    "upsample": args.upsample,
    "chain": args.chain,
    "features": args.features,
    "method": args.method,
    "reference_sample_size": args.reference_size,
    "coordinate_precision": precision,
    "variance_retained": float(reduction.GetPropertyValue("VarianceRetained")),
    "trustworthiness": float(reduction.GetPropertyValue("Trustworthiness")),
    "reduction_eigenvalues": [float(v) for v in reduction.GetPropertyValue("EigenvalueSpectrum")],
    "widgets": [widgets[i:i + 8] for i in range(0, len(widgets), 8)],
    "best_direction": best.direction,
    "worst_direction": worst.direction,
    "view_up": best.view_up,
    "best_camera": best_camera,
    "view_eigenvalues": best.eigenvalues,
    "device": best.device,
    "viewpoint_stage_ms": dict(zip(("harris", "select", "pca", "total"),
                                   [float(x) for x in bvp.GetPropertyValue("StageTimings")])),
    "stage_seconds": stages,
    "stage_peak_rss_gib": peak_gib,
    "peak_rss_gib": peak_rss_gib(),
    "images": {k: os.path.abspath(os.path.join(args.output, k + ".png"))
               for k in ("best", "worst", "dual_domain", "domain", "spectrum")
               + (("methods",) if methods else ())},
    "spectrum_figure": {"bars": spectrum_bars, "kept": 3,
                        "kept_colour": list(report_figures.KEPT_COLOUR),
                        "other_colour": list(report_figures.OTHER_COLOUR)},
    "methods": methods,
}
with open(os.path.join(args.output, "report.json"), "w") as f:
    json.dump(report, f, indent=2)

fmt = lambda v: "(%+.3f, %+.3f, %+.3f)" % tuple(v)  # noqa: E731
variance_text = ("n/a (%s has no variance spectrum)" % args.method if args.method in ("LLE", "UMAP")
                 else "%.3f" % report["variance_retained"])
print("\n%d voxels, %s features, %s: variance retained %s, trustworthiness %.3f"
      % (report["voxels"], args.features, args.method, variance_text,
         report["trustworthiness"]))
print("peak resident memory %.2f GiB (%s chain, upsample %g)"
      % (report["peak_rss_gib"], args.chain, args.upsample))
print("%d widgets seeded; best view %s, worst %s, view eigenvalues %s"
      % (len(report["widgets"]), fmt(best.direction), fmt(worst.direction),
         " ".join("%.3f" % e for e in best.eigenvalues)))
print("output: %s" % os.path.abspath(args.output))
