"""The GUI's Probe on the real brain: the time from a click to the answer (the label's
text), the former way against the present one, in one run.

    MCV_PLUGIN=build/lib/paraview-5.11/plugins/MultichannelExplorer/MultichannelExplorer.so \
        xvfb-run -a pvbatch Testing/Benchmarks/benchmark_probe.py [--clicks 7]

Chain (as a new user builds it): Colin27 T1 + AAL + Brodmann -> MergeChannels ->
MultichannelFeatures -> DimensionReduction (defaults) -> "Gaussian TF Volume" with 4
seeded widgets (auto_widgets), a 600 x 500 view, camera reset: 7.1 M voxels. The clicks
are pixels on a grid over the middle of the view (each sees the brain).

- former: the code of main before this change (9699f0b: picking.probe_at_pixel),
  reproduced below: the volume's grid read back (a one-voxel ExtractVoxels), Plot Over
  Line through the whole volume fetched, the grid read back again by probe(), the voxel
  read back, the markers shown and both views rendered before the label's text existed
  (what _gui.probe ran);
- present: _gui.probe as the GUI runs it now: the grid kept from the first click, the
  ray's voxels read back in one ExtractVoxels round trip that also brings the picked
  voxel's values, the markers moved, no render before the answer (the GUI renders after
  showing the label). The render that follows is timed too (render after answer).
Each line: median and max over the clicks, seconds. Both must pick the same voxels up
to the sampling (interpolated against nearest voxel): the picked indices are compared.
"""
import argparse
import math
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402


def former_probe_at_pixel(mce, view, x, y):
    """main's picking.probe_at_pixel at 9699f0b, as it ran (grid read back each time)."""
    from paraview import servermanager
    from multichannel_explorer import picking, _voxels
    from multichannel_explorer._common import _coordinate_tuple

    display = picking._gaussian_tf_in(view)
    source = display.Input
    _voxels._GRIDS.clear()
    grid = _voxels._Grid(source)
    origin, direction = picking.pixel_ray(view, x, y)
    hit = picking._clip_to_box(origin, direction, grid.bounds())
    if hit is None:
        return None
    t0, t1 = hit
    step = 0.5 * min(grid.spacing)
    samples = max(2, int(math.ceil((t1 - t0) / step)))
    name = picking._coordinates_name(display)
    line = servermanager.filters.PlotOverLine(Input=source)
    line.Point1 = [o + t0 * d for o, d in zip(origin, direction)]
    line.Point2 = [o + t1 * d for o, d in zip(origin, direction)]
    line.SamplingPattern = "Sample Uniformly"
    line.Resolution = samples
    polyline = servermanager.Fetch(line)
    pd = polyline.GetPointData()
    coords = pd.GetArray(name)
    valid = pd.GetArray("vtkValidPointMask")
    mask = pd.GetArray("Foreground")
    widgets = picking._widget_values(display)
    unit = float(display.ScalarOpacityUnitDistance) or 1.0
    seg = (t1 - t0) / samples
    keep, opacities = 1.0, []
    for p in range(polyline.GetNumberOfPoints()):
        alpha = 0.0
        if (valid is None or valid.GetTuple1(p)) and (mask is None or mask.GetTuple1(p) >= 0.5):
            c = list(_coordinate_tuple(coords, p)) + [0.0]
            alpha = 1.0 - (1.0 - picking._widget_alpha(widgets, c[:3])) ** (seg / unit)
        keep *= 1.0 - alpha
        opacities.append(1.0 - keep)
    seen = opacities[-1] if opacities else 0.0
    if seen < 1e-3:
        return None
    pick = next(p for p, o in enumerate(opacities) if o >= 0.5 * seen)
    point = list(polyline.GetPoint(pick))
    _voxels._GRIDS.clear()  # the former probe() read the grid again
    return mce.probe(display, position=point, view=view)  # renders both views


def stats(values):
    return "median %.3f s, max %.3f s" % (statistics.median(values), max(values))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--clicks", type=int, default=7)
    args = parser.parse_args()
    mce = T.load_plugin(globals())
    from multichannel_explorer import _gui

    reduction, view = T.default_brain_reduction((600, 500))
    display = mce.show_gaussian_tf(reduction, view)
    mce.auto_widgets(display, 4)
    simple.SetActiveView(view)
    simple.ResetCamera(view)
    simple.Render(view)
    n = reduction.GetDataInformation().GetNumberOfPoints()
    print("volume: %d voxels (%.1f M); view 600 x 500; %d clicks" % (n, n / 1e6, args.clicks))

    pixels = [(250 + 25 * (c % 4), 210 + 20 * (c // 4)) for c in range(args.clicks)]
    former, present, render, same = [], [], [], 0
    for x, y in pixels:
        start = time.perf_counter()
        old = former_probe_at_pixel(mce, view, x, y)
        former.append(time.perf_counter() - start)

        start = time.perf_counter()
        text = _gui.probe(x, y)
        present.append(time.perf_counter() - start)
        start = time.perf_counter()
        simple.Render(view)  # what the GUI does once the label is up
        render.append(time.perf_counter() - start)
        new = _gui.last_hit
        if old is not None and new is not None and text.startswith("Voxel"):
            same += max(abs(a - b) for a, b in zip(old.index, new.index)) <= 1
        print("click (%d, %d): former %.3f s -> present %.3f s (+ render %.3f s); voxel %s / %s"
              % (x, y, former[-1], present[-1], render[-1], old and tuple(old.index),
                 new and tuple(new.index)))
        sys.stdout.flush()
    print("former  (answer after both renders): %s" % stats(former))
    print("present (answer):                    %s" % stats(present))
    print("present (render after the answer):   %s" % stats(render))
    print("speed-up of the answer: %.1fx (medians); same voxel (within 1) in %d of %d clicks"
          % (statistics.median(former) / statistics.median(present), same, len(pixels)))
    sys.stdout.flush()
    os._exit(0)


main()
