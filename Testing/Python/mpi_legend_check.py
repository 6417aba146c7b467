"""The Gaussian widget legend's shares are the whole volume's, in one process and split
over MPI processes (each process counts its own piece; the counts are summed).

  pvbatch mpi_legend_check.py [--thin] [--out DIR]                     one process
  mpiexec -np R pvbatch --mpi mpi_legend_check.py [--thin] [--out DIR]  R processes
  pvpython mpi_legend_check.py --connect PORT [--thin] [--out DIR]
      a client of the (MPI) pvserver on localhost:PORT (the plugin loaded on both sides):
      the server's processes count their pieces and render, the client holds no voxel
      and draws the legend (GaussianWidgetLegend is read from the client's instance of
      the representation): the same rows.

The volume is synthetic (the shares are the point): a Wavelet grid of 50 x 20 x 10 points
whose reduced coordinates are the voxel's position (x, y, z), shown as a "Gaussian TF
Volume" with three widgets that select slabs of known widths across x, the axis the
pieces are split along: A (x <= 11: 12 of 50 columns), B (32 <= x <= 38: 7 columns) and C
(x = 25: 1 column, the layer two pieces of a 2-process run share). Known answers,
computed here from the grid: A 24%, B 14%, C 2.0%; one piece alone gives others (the
first half of a 2-process run: A 46%, B 0%, C 3.8%), and counting the shared layer twice
gives C 3.9%. A widget edit then moves A by one column (26%). --thin: 2 x 2 x 2 points,
fewer than some processes get a piece of, so that a process with no voxel takes part in
the sum; coordinates (x, y, z); A (x = 0: 4 of 8 voxels), B none, C (the voxel (1, 1, 1)). The legend text (GaussianWidgetLegend, what the view draws) must equal
the expected rows; a screenshot goes to DIR (default the test output folder).
Test driver: test_mpi_legend.sh.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

NAMES = ["A", "B", "C"]


def case(thin):
    """(grid dimensions, widgets as a flat list): centres in voxel positions, each sigma
    from the widget's half-maximum radius r (r = sigma sqrt(2 ln 2))."""
    s = 1.0 / math.sqrt(2.0 * math.log(2.0))
    if thin:
        return (2, 2, 2), [0.0, 0.5, 0.5, 0.75 * s, 0.9, 0.2, 0.2, 0.5,
                           5.0, 5.0, 5.0, 0.5 * s, 0.2, 0.9, 0.2, 0.5,
                           1.0, 1.0, 1.0, 0.5 * s, 0.2, 0.2, 0.9, 0.5]
    # Coordinates (x, 0, 0): each widget selects the columns within r of its centre's x.
    return (50, 20, 10), [5.0, 0.0, 0.0, 6.5 * s, 0.9, 0.2, 0.2, 0.5,
                          35.0, 0.0, 0.0, 3.5 * s, 0.2, 0.9, 0.2, 0.5,
                          25.0, 0.0, 0.0, 0.5 * s, 0.2, 0.2, 0.9, 0.5]


def expected_legend(dims, widgets, thin):
    """The rows the representation draws, counted here on every voxel of the grid."""
    points = [(i, j, k) for k in range(dims[2]) for j in range(dims[1]) for i in range(dims[0])]
    coords = [p if thin else (p[0], 0, 0) for p in points]
    rows = []
    for w, name in enumerate(NAMES):
        cx, cy, cz, s = widgets[8 * w:8 * w + 4]
        limit = 2.0 * math.log(2.0) * s * s
        inside = sum(1 for x in coords
                     if (x[0] - cx) ** 2 + (x[1] - cy) ** 2 + (x[2] - cz) ** 2 <= limit)
        percent = 100.0 * inside / len(coords)
        rows.append("%s  %s%%" % (name, ("%.1f" if percent < 10 else "%.0f") % percent))
    return "\n".join(rows)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--thin", action="store_true")
    parser.add_argument("--out")
    parser.add_argument("--connect", type=int, metavar="PORT")
    args = parser.parse_args()
    if args.connect is not None:
        if simple.Connect("localhost", args.connect) is None:
            print("FAIL: could not connect to a pvserver on localhost:%d" % args.connect)
            sys.stdout.flush()
            os._exit(1)
        simple.LoadPlugin(os.environ["MCV_PLUGIN"], remote=True)
        simple.LoadPlugin(os.environ["MCV_PLUGIN"], remote=False)
        import multichannel_explorer as mce
        processes = servermanager.ActiveConnection.GetNumberOfDataPartitions()
        C = T.Checker("mpi_legend_check%s (client of a pvserver of %d processes)"
                      % (" --thin" if args.thin else "", processes))
    else:
        processes, C = T.parallel_checker("mpi_legend_check%s"
                                          % (" --thin" if args.thin else ""))
        mce = T.load_plugin(globals())
    out = args.out or os.path.join(T.output_dir(), "mpi_legend")
    os.makedirs(out, exist_ok=True)

    dims, widgets = case(args.thin)
    grid = simple.Wavelet(WholeExtent=[0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1])
    calc = simple.Calculator(Input=grid, ResultArrayName="ReducedCoordinates",
                             ResultArrayType="Float",
                             Function="coords" if args.thin else "coordsX*iHat")
    calc.UpdatePipeline()
    whole = dims[0] * dims[1] * dims[2]
    points = calc.GetDataInformation().GetNumberOfPoints()
    print("%d process(es): %d points in the pieces for %d voxels" % (processes, points, whole))
    if processes > 1 and not args.thin:
        # The pieces share their boundary layers: more points in all than voxels, so the
        # run is split (else the check below would prove nothing).
        C.check(points > whole, "the volume is split over the %d processes (%d points in "
                "the pieces for %d voxels)" % (processes, points, whole))

    view = T.render_view((500, 300))
    # A pvserver renders (a volume is always drawn where its voxels are); its client draws
    # the legend over the server's image, from the counts the servers sent it.
    view.RemoteRenderThreshold = 0
    display = mce.show_gaussian_tf(calc, view, widgets=widgets)
    display.GaussianWidgetNames = NAMES
    simple.ResetCamera(view)
    label = "%s%s%d" % ("client_" if args.connect is not None else "",
                        "thin_" if args.thin else "", processes)

    def legend():
        simple.Render(view)
        display.UpdatePropertyInformation()
        return display.GetProperty("GaussianWidgetLegend").GetElement(0)

    shown = legend()
    expected = expected_legend(dims, widgets, args.thin)
    C.check(shown == expected, "%d process(es): the legend shows the whole volume's shares "
            "(expected %r, shown %r)" % (processes, expected, shown))

    # A widget edit: the shares follow (counted again, summed again).
    moved = list(widgets)
    moved[0] += 1.0  # A: x <= 12 (13 columns); --thin: the x = 1 voxels
    display.GaussianWidgets = moved
    shown = legend()
    expected = expected_legend(dims, moved, args.thin)
    C.check(shown == expected, "%d process(es): after moving widget A the legend shows "
            "%r (expected %r)" % (processes, shown, expected))
    simple.SaveScreenshot(os.path.join(out, "legend_%s.png" % label), view,
                          ImageResolution=[500, 300])
    if processes > 1 and args.connect is None:
        C.finish_parallel()
    else:
        C.finish()


main()
