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
domains of PCA, Isomap, LLE and UMAP side by side, see --no-methods), model.mcvmodel (the
reduction's fit) and transfer_function.mcvtf (the seeded widgets in that model's
coordinates: apply both to other volumes with multichannel_explorer.apply_transfer_function
or snapshot_collection.py --transfer-function, for the same colours) and report.json
(timings and peak resident memory per stage, variance retained, trustworthiness, view
directions, eigenvalues, the figures, the model files),
then prints a summary and the folder.

Outputs: the run is written into a staging folder beside the output folder
(PARENT/.NAME.run-PID), every picture and report.json checked (the PNG decodes at its size,
the JSON parses) before it is renamed into place; report.json, written last, lists only those
files. Only a finished run replaces the output folder, in one atomic exchange: a failed or
interrupted run leaves the previous complete output as it was. Before the chain runs, the
output's file system is checked (writable, room for the pictures) and the memory the chain
needs is compared with what the process may allocate (MemAvailable, cgroup, ulimit -v). A
filter that reports an error (out of memory, "needs X GiB") or a picture that was not written
(disk full, read-only file system, permission denied) stops the job with that message: exit
code 1. SIGINT / SIGTERM stop it at the filters' next progress report: exit code 130 / 143,
the staging folder removed. A second job on the same output folder stops at once (a lock).

--method UMAP reduces with UMAP instead (K = --umap-neighbors, 15).

methods.png: the four methods are fitted on the same reference sample (same size, K, L
and seed; UMAP with its own K) of a coarser grid, every --methods-stride-th voxel per axis of the features
(placing all voxels four more times would cost more than the whole job); the same
--methods-sample voxels are drawn in each, coloured by the main domain's widgets.
"""
import signal

# SIGINT / SIGTERM from the first line on (importing ParaView takes seconds): noted here,
# acted on by batch_output.StopSignals once the job has started.
_EARLY_SIGNALS = []
for _s in (signal.SIGINT, signal.SIGTERM):
    signal.signal(_s, lambda signum, frame: _EARLY_SIGNALS.append(signum))

import os  # noqa: E402
import resource  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import traceback  # noqa: E402

from paraview import servermanager, simple
from paraview.simple import *  # noqa: F401,F403

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from example_support import (DATA, add_output_options, add_reduction_options,  # noqa: E402
                             argument_parser, load_plugin, render_view, require)
import report_figures  # noqa: E402
import batch_output as B  # noqa: E402

parser = argument_parser(__doc__)
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
add_output_options(parser, os.path.join("output", "transfer_function"), (800, 600),
                   "the pictures and report.json")
add_reduction_options(parser, "Isomap", "24D")
parser.add_argument("--chain", default="fused", choices=["fused", "features"],
                    help="fused: DimensionReduction on the channels; features: "
                         "MultichannelFeatures -> DimensionReduction")
parser.add_argument("--upsample", type=float, default=1.0, metavar="F",
                    help="resample the channels by F along each axis first (trilinear)")
parser.add_argument("--neighbors", type=int, default=10, help="K of Isomap/LLE")
parser.add_argument("--umap-neighbors", type=int, default=15,
                    help="K of UMAP (see DimensionReduction's NumberOfNeighbors)")
parser.add_argument("--landmarks", type=int, default=500, help="L of landmark Isomap")
parser.add_argument("--blend", default="Composite", choices=["Composite", "Maximum Intensity"],
                    help="how the ray caster blends the samples")
parser.add_argument("--device", default="Auto", choices=["Auto", "CPU", "GPU"],
                    help="where the filters compute (Auto: the GPU when there is a usable one)")
parser.add_argument("--float16-coordinates", action="store_true",
                    help="store ReducedCoordinates as float16 (half the memory, ~1/2048 "
                         "relative precision; DimensionReduction's CoordinatePrecision)")
parser.add_argument("--seed", type=int, default=0,
                    help="random seed of the reference sample and the k-means")
parser.add_argument("--no-methods", dest="methods", action="store_false",
                    help="skip methods.png (PCA, Isomap, LLE and UMAP side by side)")
parser.add_argument("--methods-stride", type=int, default=3,
                    help="methods.png: every N-th voxel per axis is reduced")
parser.add_argument("--methods-sample", type=int, default=20000,
                    help="methods.png: voxels drawn per method")
parser.add_argument("--no-memory-check", dest="memory_check", action="store_false",
                    help="skip the job's estimate of its peak memory before it starts (the "
                         "filters still check theirs)")
args = parser.parse_args(sys.argv[1:])

inputs = [args.input] if args.input else args.channels
for path in inputs:
    require(path)
stages = {}
peak_gib = {}  # the process's peak resident memory at the end of each stage
memory_estimate = {}  # check_memory's estimate, what was available, the virtual size then
# What the job writes into the output folder (a previous run's copies are replaced).
OWN_FILES = ("best.png", "worst.png", "dual_domain.png", "domain.png", "spectrum.png",
             "methods.png", "report.json", "model.mcvmodel", "transfer_function.mcvtf")


def peak_rss_gib():
    """Peak resident memory of this process so far (ru_maxrss: KiB on Linux)."""
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0 ** 2, 3)


def _every(n):
    return "every voxel" if n <= 1 else "every %s voxel per axis" % (
        {2: "2nd", 3: "3rd"}.get(n, "%dth" % n))


def output_bytes():
    """Room the pictures and the report surely need, checked before the chain runs: an
    eighth of a byte per pixel of every picture plus 16 KiB. The outputs of the small job
    (240 x 180, no methods.png) took 141 KiB, 0.21 bytes per pixel: this is a lower bound,
    so that a disk that cannot hold them fails at once, and one that may is tried (a picture
    that does not fit then stops the job, naming it)."""
    w, h = args.size
    pixels = 4 * w * h + 900 * 560 + (2000 * 600 if args.methods else 0)
    return pixels // 8 + (16 << 10)


class Job(object):
    """The run's output folder, the stop signals and the VTK errors; check() after every
    stage turns a signal into Interrupted and a filter's error into JobError."""

    def __init__(self):
        self.signals = B.StopSignals(_EARLY_SIGNALS[0] if _EARLY_SIGNALS else None)
        self.signals.check()
        self.errors = B.VtkErrors()
        self.run = B.RunFolder(args.output, min_free_bytes=output_bytes())

    def check(self, stage):
        self.signals.check()
        messages = self.errors.take()
        if messages:
            raise B.JobError("%s failed: %s" % (stage, "; ".join(messages[:3])))

    def watch(self, proxy):
        """The filter stops at its next progress report once SIGINT / SIGTERM came."""
        return self.signals.watch(proxy)

    def save_png(self, name, write, size=None):
        """Writes OUTPUT/name through write(path) (into the staging folder), checked."""
        self.signals.check()
        B.checked_png(self.run.path(name), write, size)
        self.check("writing %s" % name)

    def screenshot(self, name, view_or_layout, size, **params):
        self.save_png(name, lambda path: SaveScreenshot(path, view_or_layout, **params), size)


job = None


def timed(name, function):
    start = time.time()
    value = function()
    job.check(name)
    stages[name] = round(time.time() - start, 3)
    peak_gib[name] = peak_rss_gib()
    print("%-22s %7.2f s   peak RSS %.2f GiB" % (name, stages[name], peak_gib[name]))
    sys.stdout.flush()
    return value


def whole_extent(proxy):
    """The extent a reader will produce, from its header only (nothing read yet)."""
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

    proxy.UpdatePipelineInformation()
    algorithm = proxy.GetClientSideObject()
    algorithm.UpdateInformation()
    info = algorithm.GetOutputInformation(0)
    key = vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT()
    return list(info.Get(key)) if info.Has(key) else None


def header_arrays(proxy):
    """The point arrays a reader announces in its pipeline information (its header: nothing
    read), at least one."""
    from vtkmodules.vtkCommonDataModel import vtkDataObject

    info = proxy.GetClientSideObject().GetOutputInformation(0)
    key = vtkDataObject.POINT_DATA_VECTOR()
    return max(1, info.Get(key).GetNumberOfInformationObjects() if info.Has(key) else 1)


def check_memory(readers):
    """Refuses the job when its estimated peak does not fit in what this process may
    allocate (B.available_memory: MemAvailable, cgroup, ulimit -v): first from the readers'
    headers alone (the arrays each announces), before anything is read, then with the arrays
    they give (a reader's data information reads it: the few bytes per voxel of one read
    may not fit under a tight ulimit -v, where VTK aborts on a failed allocation)."""
    voxels = 0
    for reader in readers:
        extent = whole_extent(reader)
        if extent is None:
            return  # nothing to estimate from: the filters' own checks remain
        count = 1
        for a in range(3):
            count *= max(1, extent[2 * a + 1] - extent[2 * a] + 1)
        voxels = max(voxels, count)
    refuse_unless_it_fits(voxels, sum(header_arrays(r) for r in readers))
    refuse_unless_it_fits(voxels, sum(max(1, len(r.PointData.keys())) if hasattr(r, "PointData")
                                      else 1 for r in readers))


def refuse_unless_it_fits(voxels, channels):
    """check_memory's estimate for `voxels` read and `channels`: a JobError when it does not
    fit."""
    read_voxels, voxels = voxels, int(voxels * args.upsample ** 3)
    need = B.job_memory_bytes(read_voxels, voxels, channels, 24 if args.features == "24D" else 6,
                              args.chain == "features", args.float16_coordinates,
                              tuple(args.size), args.methods, args.methods_stride)
    available = B.available_memory()
    memory_estimate.update(needed_gib=round(need / 2.0 ** 30, 3),
                           available_gib=round(available / 2.0 ** 30, 3)
                           if available is not None else None,
                           vm_size_at_check_gib=round((B._vm_size() or 0) / 2.0 ** 30, 3))
    if available is not None and need > available:
        raise B.JobError("the job needs %s of memory for %d voxels x %d channels (%s "
                         "features, %s chain), %s available: subsample (--upsample below "
                         "1) or free memory"
                         % (B.gib(need), voxels, channels, args.features, args.chain,
                            B.gib(available)))


def camera_of(view):
    """What best.png was rendered with: tests re-render the brain's silhouette with it."""
    return {"position": list(view.CameraPosition), "focal_point": list(view.CameraFocalPoint),
            "view_up": list(view.CameraViewUp), "view_angle": float(view.CameraViewAngle),
            "parallel_projection": int(view.CameraParallelProjection),
            "parallel_scale": float(view.CameraParallelScale),
            "size": [int(v) for v in view.ViewSize], "background": list(view.Background)}


def restore_camera(view, camera):
    """The view's camera as camera_of() saw it."""
    view.CameraPosition = camera["position"]
    view.CameraFocalPoint = camera["focal_point"]
    view.CameraViewUp = camera["view_up"]
    view.CameraParallelScale = camera["parallel_scale"]


def neighbors(method):
    return args.umap_neighbors if method == "UMAP" else args.neighbors


def save_model_files(mce, reduction, display):
    """Writes model.mcvmodel (the reduction's fit: save_model) and transfer_function.mcvtf
    (the seeded widgets, naming that model and its checksum) into the staging folder and
    reads the pair back (read_transfer_function: the model found, its checksum matching).
    Returns the report's entry; with --chain features there is no model to save (the
    reduction reads a Features array, whose normalisation the model would need), which the
    entry says."""
    if args.chain == "features":
        return {"model": None, "transfer_function": None,
                "reason": "--chain features: the reduction reads the Features array, so "
                          "there is no reduction model (use the default fused chain)"}
    model = job.run.path("model.mcvmodel")
    try:
        mce.save_model(reduction, model)
    except (RuntimeError, ValueError) as exc:  # the writer failed: find out why
        raise B.write_failure("model.mcvmodel", os.path.dirname(model), str(exc))
    job.check("writing model.mcvmodel")
    tf = job.run.path("transfer_function.mcvtf")
    B.write_text(tf, mce.transfer_function_files.transfer_function_text(display, model, tf))
    try:
        checked = mce.read_transfer_function(tf)
    except ValueError as exc:
        raise B.JobError("transfer_function.mcvtf does not read back: %s" % exc)
    return {"model": job.run.final("model.mcvmodel"),
            "model_crc32": int(checked.model_header["crc32"]),
            "model_channels": list(checked.channels),
            "transfer_function": job.run.final("transfer_function.mcvtf"),
            "widgets": len(checked.widgets) // 8}


def main():
    mce = load_plugin(args.plugin)
    # 1. Channels on one grid, and their feature vectors.
    readers = [OpenDataFile(p) for p in inputs]
    if None in readers:
        raise B.JobError("no reader for %s" % inputs[readers.index(None)])
    if args.memory_check:
        check_memory(readers)
    volume = simple.MergeChannels(Input=readers) if len(readers) > 1 else readers[0]
    job.watch(volume)
    timed("read", volume.UpdatePipeline)
    if args.upsample != 1.0:
        # ParaView's own trilinear resampling (vtkProbeFilter) onto a grid F times finer.
        extent = volume.GetDataInformation().GetExtent()
        dims = [extent[2 * a + 1] - extent[2 * a] + 1 for a in range(3)]
        volume = job.watch(simple.ResampleToImage(
            Input=volume, UseInputBounds=1,
            SamplingDimensions=[max(1, int(round(d * args.upsample))) for d in dims]))
        timed("upsample", volume.UpdatePipeline)
    if volume.GetDataInformation().GetNumberOfPoints() < 2:
        raise B.JobError("the input has no voxels: %s" % ", ".join(inputs))
    if args.chain == "features":
        features = job.watch(simple.MultichannelFeatures(
            Input=volume, FeatureSet=args.features, Device=args.device))
        timed("features", features.UpdatePipeline)
        source, feature_set = features, "Use input array"
    else:
        features, source, feature_set = volume, volume, args.features

    # 2. The reduced domain.
    precision = "Float16" if args.float16_coordinates else "Float32"
    reduction = job.watch(simple.DimensionReduction(
        Input=source, FeatureSet=feature_set, Method=args.method, OutputDimension=3,
        ReferenceSampleSize=args.reference_size, NumberOfNeighbors=neighbors(args.method),
        NumberOfLandmarks=args.landmarks, RandomSeed=args.seed, Device=args.device,
        CoordinatePrecision=precision))
    if args.chain == "features":
        reduction.Features = ["POINTS", "Features"]
    timed("reduction", reduction.UpdatePipeline)
    reduction.UpdatePropertyInformation()
    if reduction.GetDataInformation().GetPointDataInformation().GetArrayInformation(
            "ReducedCoordinates") is None:
        raise B.JobError("reduction failed: DimensionReduction produced no ReducedCoordinates")

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
        raise B.JobError("no best viewpoint for these widgets (their opacity is flat or empty)")
    job.screenshot("best.png", view, args.size)
    best_camera = camera_of(view)
    worst = mce.apply_best_viewpoint(reduction, view, which="worst", disambiguate=True)
    job.check("worst viewpoint")
    job.screenshot("worst.png", view, args.size)
    restore_camera(view, best_camera)  # the best view again, without computing it again

    # The reduced domain beside the volume, and the eigenvalue spectrum.
    dual = timed("dual domain", lambda: mce.show_dual_domain(display, view))
    job.screenshot("dual_domain.png", dual.layout, [2 * args.size[0], args.size[1]],
                   ImageResolution=[2 * args.size[0], args.size[1]])
    job.screenshot("domain.png", dual.domain_view, None)
    values, _ = report_figures.spectrum_table(reduction)
    variance = float(reduction.GetPropertyValue("VarianceRetained"))
    spectrum_bars = []
    job.save_png("spectrum.png", lambda path: spectrum_bars.append(
        report_figures.spectrum_figure(path, args.method, values, 3, variance)))
    spectrum_bars = spectrum_bars[0]

    def coarse(source):
        """Every --methods-stride-th voxel of `source` per axis."""
        rate = max(1, args.methods_stride)
        return job.watch(simple.ExtractSubset(Input=source, SampleRateI=rate,
                                              SampleRateJ=rate, SampleRateK=rate))

    def fetch_array(source, name, port=0, data=None):
        """The point array `name` of `source`'s output (`data`: that output, already
        fetched), as numpy."""
        from vtkmodules.util.numpy_support import vtk_to_numpy

        data = servermanager.Fetch(source, idx=port) if data is None else data
        array = data.GetPointData().GetArray(name)
        job.check("fetching %s" % name)
        if array is None:
            raise B.JobError("%s: no %s array in its output" % (
                source.GetXMLLabel(), name))
        # Coordinates may be float16 (--float16-coordinates): decoded to float32.
        return mce.coordinate_values(array) if name == "ReducedCoordinates" \
            else vtk_to_numpy(array)

    def reduce_coarse(method, coarse_features):
        """The main reduction's settings (reference size, K, L, seed) with another method,
        on the coarse grid; returns the proxy, updated."""
        other = job.watch(simple.DimensionReduction(
            Input=coarse_features, FeatureSet=feature_set, Method=method, OutputDimension=3,
            ReferenceSampleSize=args.reference_size, NumberOfNeighbors=neighbors(method),
            NumberOfLandmarks=args.landmarks, RandomSeed=args.seed, Device=args.device,
            CoordinatePrecision=precision))
        if args.chain == "features":
            other.Features = ["POINTS", "Features"]
        other.UpdatePipeline()
        job.check("methods (%s)" % method)
        other.UpdatePropertyInformation()
        return other

    def method_panels():
        """The same sampled voxels of the coarse grid in the domains of PCA, Isomap, LLE and
        UMAP, each in the colour of the main domain's widget that selects it there (at the
        main domain's coordinates of those voxels, ReducedDomain's points)."""
        coarse_features = coarse(features)
        shown = job.watch(simple.ReducedDomain(
            Input=coarse(reduction), SampleSize=args.methods_sample, RandomSeed=args.seed,
            GaussianWidgets=widgets))
        shown.Coordinates = ["POINTS", "ReducedCoordinates"]
        cloud = servermanager.Fetch(shown)  # points at the main domain's coordinates
        voxels = fetch_array(shown, "VoxelId", data=cloud)
        colours = report_figures.widget_colours(
            [cloud.GetPoint(i) for i in range(cloud.GetNumberOfPoints())],
            [float(v) for v in widgets])
        panels = []
        for method in ("PCA", "Isomap", "LLE", "UMAP"):
            start = time.time()
            other = reduce_coarse(method, coarse_features)
            xyz = fetch_array(other, "ReducedCoordinates")[voxels]
            panels.append(dict(
                name=method, x=xyz[:, 0].tolist(), y=xyz[:, 1].tolist(), colours=colours,
                variance_retained=float(other.GetPropertyValue("VarianceRetained")),
                variance_spectrum=bool(other.GetPropertyValue("VarianceSpectrum")),
                trustworthiness=float(other.GetPropertyValue("Trustworthiness")),
                seconds=round(time.time() - start, 3)))
            Delete(other)
        grid = coarse_features.GetDataInformation().GetNumberOfPoints()
        return panels, grid, len(voxels)

    methods = None
    if args.methods:
        panels, grid, drawn = timed("methods", method_panels)
        caption = ("%s features of %s (%d voxels); each method fitted on the same %d-voxel "
                   "reference sample (seed=%d, K=%d, UMAP's K=%d, L=%d); the same %d voxels "
                   "drawn at dimensions 1-2, in the colour of the %s domain's widget that "
                   "selects them (within 1.18 sigma of its centre: half its peak; the others "
                   "grey)"
                   % (args.features, _every(args.methods_stride), grid, args.reference_size,
                      args.seed, args.neighbors, args.umap_neighbors, args.landmarks, drawn,
                      args.method))
        job.save_png("methods.png", lambda path: report_figures.methods_figure(
            path, panels, caption))
        methods = {p["name"]: {k: p[k] for k in ("variance_retained", "trustworthiness",
                                                 "seconds")} for p in panels}
        methods.update(grid_voxels=grid, voxels_drawn=drawn, stride=args.methods_stride)

    # The fit and the widgets as files (model.mcvmodel, transfer_function.mcvtf): applied to
    # other volumes (apply_transfer_function, snapshot_collection.py --transfer-function),
    # they give the same tissue the same colours as here.
    model_files = timed("model files", lambda: save_model_files(mce, reduction, display))

    # Report: written last, listing the pictures that are in the staging folder, checked.
    bvp = best.filter
    images = [k for k in ("best", "worst", "dual_domain", "domain", "spectrum", "methods")
              if os.path.exists(job.run.path(k + ".png"))]
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
        "variance_spectrum": bool(reduction.GetPropertyValue("VarianceSpectrum")),
        "trustworthiness": float(reduction.GetPropertyValue("Trustworthiness")),
        "reduction_eigenvalues": [float(v) for v in
                                  reduction.GetPropertyValue("EigenvalueSpectrum")],
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
        "memory_estimate": dict(memory_estimate,
                                vm_peak_gib=round((B._vm_size("VmPeak") or 0) / 2.0 ** 30, 3)),
        "images": {k: job.run.final(k + ".png") for k in images},
        "spectrum_figure": {"bars": spectrum_bars, "kept": 3,
                            "kept_colour": list(report_figures.KEPT_COLOUR),
                            "other_colour": list(report_figures.OTHER_COLOUR)},
        "methods": methods,
        "model_files": model_files,
    }
    job.signals.check()
    B.write_json(job.run.path("report.json"), report)
    job.signals.check()
    job.run.commit(OWN_FILES)

    fmt = lambda v: "(%+.3f, %+.3f, %+.3f)" % tuple(v)  # noqa: E731
    variance_text = ("n/a (%s has no variance spectrum)" % args.method
                     if not report["variance_spectrum"] else "%.3f" % report["variance_retained"])
    print("\n%d voxels, %s features, %s: variance retained %s, trustworthiness %.3f"
          % (report["voxels"], args.features, args.method, variance_text,
             report["trustworthiness"]))
    print("peak resident memory %.2f GiB (%s chain, upsample %g)"
          % (report["peak_rss_gib"], args.chain, args.upsample))
    print("%d widgets seeded; best view %s, worst %s, view eigenvalues %s"
          % (len(report["widgets"]), fmt(best.direction), fmt(worst.direction),
             " ".join("%.3f" % e for e in best.eigenvalues)))
    print("output: %s" % os.path.abspath(args.output))


def run():
    """The job; returns its exit code: 0 done, 1 an error (one line on stderr, the output
    folder as it was), 130 / 143 SIGINT / SIGTERM (the output folder as it was)."""
    global job
    code = 0
    try:
        job = Job()
        main()
    except B.Interrupted as exc:
        print("stopped: %s; the output folder is as it was before this run" % exc,
              file=sys.stderr)
        code = exc.exit_code
    except B.JobError as exc:
        print("error: %s" % exc, file=sys.stderr)
        code = B.EXIT_ERROR
    except Exception as exc:  # a stage's empty output met by the next one: say why
        signum = job.signals.signum if job is not None else None
        messages = job.errors.take() if job is not None else []
        if signum is not None:
            print("stopped: interrupted by %s" % B.signal.Signals(signum).name, file=sys.stderr)
            code = 128 + signum
        else:
            if messages:
                print("error: %s" % "; ".join(messages[:3]), file=sys.stderr)
            else:
                traceback.print_exc()
                print("error: %s: %s" % (type(exc).__name__, exc), file=sys.stderr)
            code = B.EXIT_ERROR
    finally:
        if job is not None and not job.run.committed:
            job.run.abandon()
    return code


if __name__ == "__main__":
    exit_code = run()
    sys.stdout.flush()
    sys.stderr.flush()
    # os._exit: pvbatch 5.11 crashes in its teardown after sys.exit, and its own exit path
    # does not keep the code.
    os._exit(exit_code)
