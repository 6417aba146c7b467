"""The representation's own work per widget edit, per sample against per voxel.

    xvfb-run -a pvbatch Testing/Benchmarks/benchmark_widget_edit.py [--sizes 100,181x217x181,318]

For each volume (3-component float32 reduced coordinates, a smooth field over the
volume, two widgets) and each classification of the "Gaussian TF Volume": one render
(the data is delivered; per sample the coordinate texture is built), then --edits widget
edits, each followed by a render. The representation times its own preparation of every
render (GaussianTFPreparationSeconds: from the start of its render-time update to the
end of its data preparation, i.e. the RGBA pass per voxel, uniforms per sample); the
median over the edits is that classification's work per edit. The ray casting itself
(llvmpipe here, the GPU elsewhere) is the same work for both and is not counted. Prints a
table and the ratio per voxel / per sample at each size.
"""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402

from paraview import simple  # noqa: E402


def parse_size(text):
    dims = [int(v) for v in text.split("x")]
    return dims * 3 if len(dims) == 1 else dims


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="100,181x217x181,318",
                        help="volume sizes, N (N^3) or XxYxZ (default: 1 M, 7.1 M, 32 M)")
    parser.add_argument("--edits", type=int, default=7)
    args = parser.parse_args()
    mce = T.load_plugin(globals())

    view = simple.CreateView("RenderView")
    view.ViewSize = [200, 200]
    view.OrientationAxesVisibility = 0
    rows = []
    for text in args.sizes.split(","):
        dims = parse_size(text)
        extent = [0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1]
        source = simple.Wavelet(WholeExtent=extent)
        coords = simple.Calculator(
            Input=source, ResultArrayName="ReducedCoordinates", ResultArrayType="Float",
            Function="coordsX/%d*iHat + coordsY/%d*jHat + (RTData-37)/240*kHat"
                     % (dims[0], dims[1]))
        coords.UpdatePipeline()
        voxels = dims[0] * dims[1] * dims[2]
        row = {"voxels": voxels}
        for mode in ("Per sample", "Per voxel"):
            display = mce.show_gaussian_tf(coords, view)
            display.Classification = mode
            display.Device = "CPU"
            display.GaussianWidgets = [0.3, 0.5, 0.5, 0.1, 1, 0, 0, 0.5,
                                       0.7, 0.5, 0.5, 0.1, 0, 1, 0, 0.5]
            simple.ResetCamera(view)
            simple.Render(view)
            display.UpdatePropertyInformation()
            first = float(display.GetPropertyValue("GaussianTFPreparationSeconds"))
            builds = int(display.GetPropertyValue("GaussianTFTextureBuilds"))
            times = []
            for e in range(args.edits):
                display.GaussianWidgets = [0.3 + 0.01 * e, 0.5, 0.5, 0.1, 1, 0, 0, 0.5,
                                           0.7, 0.5, 0.5, 0.1 + 0.01 * e, 0, 1, 0, 0.5]
                simple.Render(view)
                display.UpdatePropertyInformation()
                times.append(float(display.GetPropertyValue("GaussianTFPreparationSeconds")))
            display.UpdatePropertyInformation()
            row[mode] = (statistics.median(times), first,
                         int(display.GetPropertyValue("GaussianTFTextureBuilds")) - builds)
            simple.Hide(coords, view)
            simple.Delete(display)
        rows.append(row)
        simple.Delete(coords)
        simple.Delete(source)

    G.print_mode_table(
        rows, "work per edit", ["first render (texture / RGBA) per sample, per voxel"],
        lambda s, v: ["%.0f ms, %.0f ms" % (1e3 * s[1], 1e3 * v[1])])
    for row in rows:
        if row["Per sample"][2] != 0:
            print("  (!) %.1f M voxels: per sample built the texture %d times during the edits"
                  % (row["voxels"] / 1e6, row["Per sample"][2]))
    sys.stdout.flush()
    os._exit(0)


main()
