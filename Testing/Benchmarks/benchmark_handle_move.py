"""Cost of one handle move on the real brain: a property set of one widget's centre (what
the domain view's handle does at every mouse move) up to the end of the representation's
update, per sample against per voxel, at 7.1 M voxels and on a 1 M-voxel block of it.

    xvfb-run -a pvbatch Testing/Benchmarks/benchmark_handle_move.py [--moves 9]

The chain is the main job's (Examples/transfer_function.py): Colin27 T1 + AAL + Brodmann
-> MultichannelFeatures 24D -> DimensionReduction (landmark Isomap, 10000 reference
voxels, 500 landmarks, K = 10, seed 0) -> "Gaussian TF Volume" with 4 widgets seeded at
the k-means clusters (auto_widgets). The 1 M-voxel volume is the central 100^3 block of
the channels (ExtractSubset), reduced the same way. For each volume and classification:
one render (data delivered; per sample the coordinate texture is built), then --moves
moves of widget 1's centre by 1 % of the domain's extent, each one
`display.GaussianWidgets = ...` (set + UpdateVTKObjects) followed by a render. Printed,
medians over the moves:
- prepare: the representation's own update (GaussianTFPreparationSeconds: from the
  start of its render-time update to the end of its data preparation: uniforms per
  sample, the RGBA pass per voxel on the CPU);
- set: the property set alone (client side, as the handle does it);
- to frame: from the set to the end of the render (includes the ray casting on Mesa
  llvmpipe here, the same work for both classifications).

With --turn, instead: the frame time of the volume while the camera turns, ParaView's
plain "Volume" representation of one channel (the first, the T1) against the "Gaussian TF
Volume" per sample (the baked table, PerSampleEvaluation's default, and the exact
evaluation of every widget) and per voxel, on the same grid, view and sample distance:

    xvfb-run -a pvbatch Testing/Benchmarks/benchmark_handle_move.py --turn \
        [--widgets 1,8,64] [--grids 100,181x217x181,318] [--frames 7] [--size 800 600]
        [--reduced brain_reduced.vti] [--skipping] [--exact-only] [--whole-box]

--whole-box adds the plain volume and the exact evaluation with their opacity per unit
length divided by 1e6 (the same shaders; no ray terminates early, so both take every
sample of the box): the cost of a sample of each at the same sample count. --skipping adds
the exact evaluation with EmptySpaceSkipping On (the other columns: Off),
its brick statistics, its picture against the exact one and what Automatic (the
default) picks; --exact-only leaves out the table and per voxel; --sigma-scale S multiplies
every seeded sigma by S (wider widgets: a coarser table).

The whole brain is reduced once (the chain above) and resampled (ResampleToImage) to each
grid; --widgets widgets seeded by auto_widgets. Each of the four is a display of its own
copy of the grid (PassArrays), shown alone; a round renders each once at the same
camera angle, the camera turns 360/--frames degrees between rounds, after one warm-up
round (textures uploaded). A widget the seeding starts hidden (the cluster of more than
half of the voxels: the only one with --widgets 1) is shown at opacity 0.05. Prints the
medians and each one's ratio to the plain volume, the baked table's size and the time
to bake it (the representation's preparation after the widgets are set), and the plain
volume's sample rate: the samples of every ray through the volume's box (its chord over
the sample distance VTK picks, the smallest spacing, before early ray termination) per
second of its frame time.
"""
import argparse
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ray_samples  # noqa: E402

from paraview import simple  # noqa: E402

CHANNELS = ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")


def reduced(volume):
    """The main job's features and landmark Isomap on `volume`, updated."""
    features = simple.MultichannelFeatures(Input=volume, FeatureSet="24D", Device="CPU")
    reduction = simple.DimensionReduction(
        Input=features, Method="Isomap", OutputDimension=3, ReferenceSampleSize=10000,
        NumberOfNeighbors=10, NumberOfLandmarks=500, RandomSeed=0, Device="CPU")
    reduction.Features = ["POINTS", "Features"]
    start = time.time()
    reduction.UpdatePipeline()
    return reduction, time.time() - start


def measure(mce, view, reduction, mode, moves):
    display = mce.show_gaussian_tf(reduction, view, classification=mode)
    display.Device = "CPU"
    widgets = [float(v) for v in mce.auto_widgets(display, 4, seed=0)]
    simple.ResetCamera(view)
    simple.Render(view)
    coords = reduction.PointData["ReducedCoordinates"]
    extent = max(hi - lo for lo, hi in (coords.GetRange(c) for c in range(3)))
    prepare, setting, frame = [], [], []
    for m in range(moves):
        values = list(widgets)
        values[0] += 0.01 * extent * (m + 1)  # widget 1's centre, as a handle drag
        start = time.perf_counter()
        display.GaussianWidgets = values
        set_done = time.perf_counter()
        simple.Render(view)
        end = time.perf_counter()
        display.UpdatePropertyInformation()
        prepare.append(float(display.GetPropertyValue("GaussianTFPreparationSeconds")))
        setting.append(set_done - start)
        frame.append(end - start)
    simple.Hide(reduction, view)
    simple.Delete(display)
    return [statistics.median(x) for x in (prepare, setting, frame)]


def parse_size(text):
    dims = [int(v) for v in text.split("x")]
    return dims * 3 if len(dims) == 1 else dims


def picture(path):
    """RGB of a screenshot as an int array."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader

    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    return vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)[:, None, :]


def box_samples(view, bounds, spacing):
    """Ray samples of a frame of `view` through the box `bounds` at a sample distance of the
    smallest spacing (VTK's automatic sample distance), without early termination."""
    return ray_samples.box_samples(view.GetActiveCamera(), view.ViewSize, bounds, min(spacing))


def turn(mce, view, reduction, args):
    """The --turn table (see the module's doc)."""
    native = list(reduction.GetDataInformation().GetExtent())
    native = [native[1] - native[0] + 1, native[3] - native[2] + 1, native[5] - native[4] + 1]
    counts = [int(v) for v in args.widgets.split(",")]
    # name: (classification, PerSampleEvaluation, EmptySpaceSkipping)
    settings = {"table": ("Per sample", "Baked table", 0),
                "exact": ("Per sample", "Exact", 0),
                "exact, skipping": ("Per sample", "Exact", 1),
                "exact, whole box": ("Per sample", "Exact", 0),
                "per voxel": ("Per voxel", "Baked table", 0)}
    modes = ["plain"] + (["plain, whole box"] if args.whole_box else []) + \
        ([] if args.exact_only else ["table"]) + ["exact"] + \
        (["exact, whole box"] if args.whole_box else []) + \
        (["exact, skipping"] if args.skipping else []) + ([] if args.exact_only else ["per voxel"])
    rows = []
    for text in args.grids.split(","):
        dims = parse_size(text)
        grid = reduction
        if dims != native:
            grid = simple.ResampleToImage(Input=reduction, SamplingDimensions=dims,
                                          UseInputBounds=1)
        grid.UpdatePipeline()
        voxels = dims[0] * dims[1] * dims[2]
        info = grid.GetDataInformation()
        bounds = info.GetBounds()
        extent = info.GetExtent()
        spacing = [(bounds[2 * a + 1] - bounds[2 * a]) / max(extent[2 * a + 1] - extent[2 * a], 1)
                   for a in range(3)]
        copies = {m: simple.PassArrays(Input=grid) for m in modes}
        displays = {}
        plain = simple.Show(copies["plain"], view)
        plain.SetRepresentationType("Volume")
        names = [n for n in grid.PointData.keys()
                 if grid.PointData[n].GetNumberOfComponents() == 1
                 and n not in ("Foreground", "vtkValidPointMask", "ModelDistance")]
        channel = next((n for n in names if "ch2" in n.lower()), names[0])
        simple.ColorBy(plain, ("POINTS", channel))
        plain.RescaleTransferFunctionToDataRange(True, False)
        displays["plain"] = plain
        if args.whole_box:
            # The same shader and samples, with the opacity per unit length divided by 1e6:
            # no ray reaches VTK's early termination, every sample of the box is taken.
            whole = simple.Show(copies["plain, whole box"], view)
            whole.SetRepresentationType("Volume")
            simple.ColorBy(whole, ("POINTS", channel))
            whole.ScalarOpacityUnitDistance = 1.0e6 * min(spacing)
            displays["plain, whole box"] = whole
        gaussian = [m for m in modes[1:] if m in settings]
        for m in gaussian:
            classification, evaluation, skipping = settings[m]
            d = mce.show_gaussian_tf(copies[m], view, classification=classification)
            d.Device = "CPU"
            d.ShowWidgetLegend = 0
            d.PerSampleEvaluation = evaluation
            d.EmptySpaceSkipping = skipping
            if m.endswith("whole box"):
                d.ScalarOpacityUnitDistance = 1.0e6 * min(spacing)  # as the plain one's
            displays[m] = d
        for count in counts:
            widgets = [float(v) for v in mce.auto_widgets(displays["exact"], count, seed=0)]
            for i in range(len(widgets) // 8):
                if widgets[8 * i + 7] <= 0:  # the seeding hides a cluster of most voxels
                    widgets[8 * i + 7] = 0.05
                widgets[8 * i + 3] *= args.sigma_scale
            for m in gaussian:
                displays[m].GaussianWidgets = widgets
            visible = sum(1 for i in range(len(widgets) // 8) if widgets[8 * i + 7] > 0)
            sigmas = [widgets[8 * i + 3] for i in range(len(widgets) // 8)
                      if widgets[8 * i + 7] > 0]
            camera = view.GetActiveCamera()
            times = {m: [] for m in modes}
            samples = []
            for r in range(args.frames + 1):
                for m in modes:
                    for other in modes:
                        displays[other].Visibility = 1 if other == m else 0
                    if r == 0 and m == modes[0]:
                        simple.ResetCamera(view)
                    start = time.perf_counter()
                    simple.Render(view)
                    if r > 0:
                        times[m].append(time.perf_counter() - start)
                if r > 0:
                    samples.append(box_samples(view, bounds, spacing))
                camera.Azimuth(360.0 / args.frames)
            # The last angle's pictures, through the table and exact: the largest channel
            # difference and the share of pixels more than 2/255 apart.
            shots = {}
            compared = [m for m in ("table", "exact, skipping") if m in modes]
            # With --whole-box the plain volume's too: how opaque its picture is (how early
            # its rays stop) beside the Gaussian TF Volume's.
            for m in compared + ["exact"] + (["plain"] if args.whole_box else []):
                for other in modes:
                    displays[other].Visibility = 1 if other == m else 0
                simple.Render(view)
                path = os.path.join(args.pictures, "turn_%.1fM_%dw_%s.png"
                                    % (voxels / 1e6, count, m.replace(" ", "_").replace(",", "")))
                simple.SaveScreenshot(path, view, ImageResolution=list(args.size))
                shots[m] = picture(path)
            differences = {}
            for m in compared:
                diff = abs(shots[m] - shots["exact"]).max(axis=2)
                differences[m] = (int(diff.max()), float((diff > 2).mean()))
            largest, share = differences.get("table", (-1, 0.0))
            bricks = None
            if "exact, skipping" in modes:
                displays["exact, skipping"].UpdatePropertyInformation()
                total = int(displays["exact, skipping"].GetPropertyValue("GaussianTFBricks"))
                empty = int(displays["exact, skipping"].GetPropertyValue("GaussianTFEmptyBricks"))
                listed = float(displays["exact, skipping"].GetPropertyValue(
                    "GaussianTFWidgetsPerBrick"))
                # What EmptySpaceSkipping's default (Automatic) picks for these widgets.
                for other in modes:
                    displays[other].Visibility = 1 if other == "exact, skipping" else 0
                displays["exact, skipping"].EmptySpaceSkipping = "Automatic"
                simple.Render(view)
                displays["exact, skipping"].UpdatePropertyInformation()
                automatic = int(displays["exact, skipping"].GetPropertyValue(
                    "GaussianTFSkippingUsed"))
                displays["exact, skipping"].EmptySpaceSkipping = "On"
                bricks = (total, empty, listed) + differences["exact, skipping"] + (automatic,)
            # A handle move (widget 1's centre by a tenth of its sigma): the table is baked
            # again; the representation's preparation is that bake and the uniforms.
            # With skipping, the widget table is rebuilt too: its preparation is measured alike.
            bake, used, rebuild = 0.0, "no table", {}
            for m in [m for m in ("table", "exact, skipping") if m in modes]:
                for other in modes:
                    displays[other].Visibility = 1 if other == m else 0
                moved = list(widgets)
                moved[0] += 0.1 * widgets[3]
                displays[m].GaussianWidgets = moved
                simple.Render(view)
                displays[m].UpdatePropertyInformation()
                rebuild[m] = float(displays[m].GetPropertyValue("GaussianTFPreparationSeconds"))
                if m == "table":
                    bake = rebuild[m]
                    used = str(displays[m].GetPropertyValue("GaussianTFEvaluationUsed"))
            if bricks:
                bricks += (rebuild["exact, skipping"],)  # index 6
            med = {m: statistics.median(times[m]) for m in modes}
            rate = statistics.median(samples) / med["plain"]
            rows.append((voxels, count, visible, med, used, bake, rate, min(sigmas), largest, share,
                         bricks))
            print("%.1f M voxels (%s), %d widgets (%d visible, narrowest sigma %.3g): "
                  % (voxels / 1e6, channel, count, visible, min(sigmas))
                  + ", ".join("%s %.0f ms" % (m, 1e3 * med[m]) for m in modes)
                  + "; %s, baked in %.1f ms; plain: %.3g M box samples per frame, %.1f M/s"
                  % (used, 1e3 * bake, statistics.median(samples) / 1e6, rate / 1e6)
                  + "; table vs exact picture: largest %d/255, %.3f %% of pixels > 2/255"
                  % (largest, 100 * share)
                  + ("; bricks %d, %d empty, %.2f widgets per reached brick; skipping vs exact "
                     "picture: largest %d/255, %.3f %% of pixels > 2/255"
                     % (bricks[:3] + (bricks[3], 100 * bricks[4])) if bricks else "")
                  + ("; skipping's preparation after a move %.1f ms; Automatic uses the bricks: %s"
                     % (1e3 * bricks[6], "yes" if bricks[5] else "no") if bricks else ""))
            sys.stdout.flush()
        for m in modes:
            simple.Delete(displays[m])
            simple.Delete(copies[m])
        if grid is not reduction:
            simple.Delete(grid)

    print("\n| voxels | widgets | plain Volume (box samples/s) | "
          + " | ".join("%s (x plain)" % m for m in modes[1:])
          + " | table, bake | table vs exact picture |"
          + (" empty bricks, widgets per reached brick, rebuild | skipping vs exact picture |"
             " Automatic draws |"
             if args.skipping else ""))
    print("|---" * (len(modes) + 4 + (3 if args.skipping else 0)) + "|")
    for voxels, count, visible, med, used, bake, rate, sigma, largest, share, bricks in rows:
        p = med["plain"]
        print("| %.1f M | %d (%d visible) | %.0f ms (%.0f M/s) | " % (voxels / 1e6, count, visible,
                                                                   1e3 * p, rate / 1e6)
              + " | ".join("%.0f ms (x%.2f)" % (1e3 * med[m], med[m] / p) for m in modes[1:])
              + " | %s, %.0f ms | %d/255, %.2f %% > 2/255 |"
              % (used.replace("table ", ""), 1e3 * bake, largest, 100 * share)
              + (" %.0f %%, %.1f, %.0f ms | %d/255, %.2f %% > 2/255 | %s |"
                 % (100.0 * bricks[1] / max(bricks[0], 1), bricks[2], 1e3 * bricks[6], bricks[3],
                    100 * bricks[4], "skipping" if bricks[5] else "exact")
                 if bricks else ""))
    sys.stdout.flush()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--moves", type=int, default=9)
    parser.add_argument("--size", type=int, nargs=2, default=None,
                        help="view size (default 400 400; 800 600 with --turn)")
    parser.add_argument("--turn", action="store_true", help="the frame-time table instead")
    parser.add_argument("--widgets", default="1,8,64")
    parser.add_argument("--grids", default="100,181x217x181,318")
    parser.add_argument("--frames", type=int, default=7)
    parser.add_argument("--pictures", default=".",
                        help="--turn: folder of the table's and the exact pictures")
    parser.add_argument("--sigma-scale", type=float, default=1.0,
                        help="--turn: every seeded widget's sigma times this")
    parser.add_argument("--exact-only", action="store_true",
                        help="--turn: leave out the baked table and per voxel")
    parser.add_argument("--skipping", action="store_true",
                        help="--turn: also the exact evaluation with EmptySpaceSkipping")
    parser.add_argument("--whole-box", action="store_true",
                        help="--turn: also the plain volume with no early ray termination")
    parser.add_argument("--reduced", default="",
                        help="--turn: a .vti of the reduced brain, written by the first run "
                             "and read by the next ones")
    args = parser.parse_args()
    if args.size is None:
        args.size = [800, 600] if args.turn else [400, 400]
    mce = T.load_plugin(globals())
    data = os.environ.get("MCV_DATA_DIR") or os.path.join(T.REPO, ".cache", "volumes")
    paths = [os.path.join(data, n) for n in CHANNELS]
    if not all(os.path.exists(p) for p in paths):
        print("SKIP: the brain's channels are not in %s (scripts/fetch-data.sh)" % data)
        sys.stdout.flush()
        os._exit(125)
    brain = simple.AppendAttributes(Input=[simple.OpenDataFile(p) for p in paths])
    brain.UpdatePipeline()
    block = simple.ExtractSubset(Input=brain, VOI=[40, 139, 58, 157, 40, 139])

    view = simple.CreateView("RenderView")
    view.ViewSize = list(args.size)
    view.OrientationAxesVisibility = 0
    if args.turn:
        if args.reduced and os.path.exists(args.reduced):
            reduction = simple.XMLImageDataReader(FileName=[args.reduced])
            reduction.UpdatePipeline()
            print("reduced brain read from %s" % args.reduced)
        else:
            reduction, seconds = reduced(brain)
            print("brain reduced in %.1f s" % seconds)
            if args.reduced:
                simple.SaveData(args.reduced, proxy=reduction)
        sys.stdout.flush()
        turn(mce, view, reduction, args)
        os._exit(0)
    rows = []
    for name, volume in (("block", block), ("brain", brain)):
        reduction, seconds = reduced(volume)
        voxels = reduction.GetDataInformation().GetNumberOfPoints()
        print("%s: %d voxels, reduced in %.1f s" % (name, voxels, seconds))
        sys.stdout.flush()
        row = {"voxels": voxels}
        for mode in ("Per sample", "Per voxel"):
            row[mode] = measure(mce, view, reduction, mode, args.moves)
            print("  %-10s prepare %.3f ms, set %.2f ms, to frame %.0f ms"
                  % ((mode,) + tuple(1e3 * v for v in row[mode])))
            sys.stdout.flush()
        rows.append(row)

    G.print_mode_table(
        rows, "prepare",
        ["set (per sample, per voxel)", "set to frame (per sample, per voxel)"],
        lambda s, v: ["%.2f ms, %.2f ms" % (1e3 * s[1], 1e3 * v[1]),
                      "%.0f ms, %.0f ms" % (1e3 * s[2], 1e3 * v[2])])
    if len(rows) == 2:
        (a, b) = rows
        print("7.1 M / 1 M: voxels %.1fx; prepare per sample %.2fx, per voxel %.2fx"
              % (b["voxels"] / a["voxels"], b["Per sample"][0] / max(a["Per sample"][0], 1e-9),
                 b["Per voxel"][0] / max(a["Per voxel"][0], 1e-9)))
    sys.stdout.flush()
    os._exit(0)


main()
