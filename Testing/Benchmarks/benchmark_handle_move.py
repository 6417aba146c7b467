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
"""
import argparse
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import mcv_testing as T  # noqa: E402

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


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--moves", type=int, default=9)
    parser.add_argument("--size", type=int, nargs=2, default=[400, 400])
    args = parser.parse_args()
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

    print("\n| voxels | per sample: prepare | per voxel: prepare | per voxel / per sample "
          "| set (per sample, per voxel) | set to frame (per sample, per voxel) |")
    print("|---|---|---|---|---|---|")
    for row in rows:
        s, v = row["Per sample"], row["Per voxel"]
        print("| %.1f M | %.3f ms | %.1f ms | %.0fx | %.2f ms, %.2f ms | %.0f ms, %.0f ms |"
              % (row["voxels"] / 1e6, 1e3 * s[0], 1e3 * v[0], v[0] / max(s[0], 1e-9),
                 1e3 * s[1], 1e3 * v[1], 1e3 * s[2], 1e3 * v[2]))
    if len(rows) == 2:
        (a, b) = rows
        print("7.1 M / 1 M: voxels %.1fx; prepare per sample %.2fx, per voxel %.2fx"
              % (b["voxels"] / a["voxels"], b["Per sample"][0] / max(a["Per sample"][0], 1e-9),
                 b["Per voxel"][0] / max(a["Per voxel"][0], 1e-9)))
    sys.stdout.flush()
    os._exit(0)


main()
