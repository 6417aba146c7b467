"""One fit for every time step: DimensionReduction's FitTime "One time step" on a 3-step
series of the real brain (Colin27 T1 + AAL atlas, every 3rd voxel) whose step 1 repeats
step 0 and whose step 2 is step 0 with the T1 brightened x 1.2.

Known answers:
- step 0 gets exactly the coordinates of a fit on that volume alone (same settings);
- step 1 (the same voxels) gets exactly step 0's coordinates, placed with step 0's fit;
- step 2 moves: the brightening is visible (coordinates and picture change), where a fit
  per step (FitTime "Each time step", ZScore) normalises it away;
- FitTimeStep 2 fits on step 2 and places step 0 with that fit;
- the fit is made once: the later steps name it as their model.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
import numpy as np  # noqa: E402
from paraview.simple import (CreateView, GetAnimationScene, Hide, OpenDataFile,  # noqa: E402
                             Render, SaveScreenshot)
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

C = T.Checker("test_fit_time")
OUT = os.path.join(T.output_dir(), "fit_time")
os.makedirs(OUT, exist_ok=True)


series, times, steps, t1, aal = T.opened_brain_series(C, OUT)
foreground = t1.ravel() > 0

alone = OpenDataFile(steps[0])
fit_alone, _ = T.coordinates_at(T.pca_reduction(mce, alone), 0.0)

one = T.pca_reduction(mce, series, FitTime="One time step", FitTimeStep=0)
at = [T.coordinates_at(one, t) for t in times]
C.check(at[0][0] is not None and np.array_equal(at[0][0], fit_alone),
        "step 0 gets exactly the coordinates of a fit on that volume alone")
C.check(at[1][0] is not None and np.array_equal(at[1][0], at[0][0]),
        "step 1 (the same voxels) keeps step 0's coordinates exactly")
moved = None if at[2][0] is None else np.linalg.norm(at[2][0] - at[0][0], axis=1)[foreground]
C.check(moved is not None and float(np.median(moved)) > 0.05,
        "step 2 (T1 x 1.2) moves with one fit: median shift %.3f of the foreground"
        % (-1 if moved is None else float(np.median(moved))))
C.check(at[1][1] is not None and at[2][1] is not None and "fit of time" in at[1][1][0] and
        at[0][1] is None,
        "steps 1 and 2 name the fit of step 0 as their model: %s" % (at[1][1],))

each = T.pca_reduction(mce, series)
each_at = [T.coordinates_at(each, t) for t in times]
shift_each = np.linalg.norm(each_at[2][0] - each_at[0][0], axis=1)[foreground]
print("     a fit per step (ZScore) moves step 2 by a median %.4f (one fit: %.3f)"
      % (float(np.median(shift_each)), float(np.median(moved))))
C.check(float(np.median(shift_each)) < float(np.median(moved)) / 5,
        "a fit per step normalises the brightening away (median %.4f vs %.3f with one fit)"
        % (float(np.median(shift_each)), float(np.median(moved))))

last = T.pca_reduction(mce, series, FitTime="One time step", FitTimeStep=5)  # clamped to step 2
last_at = [T.coordinates_at(last, t) for t in (times[2], times[0])]
step2_alone, _ = T.coordinates_at(T.pca_reduction(mce, OpenDataFile(steps[2])), 0.0)
C.check(last_at[0][0] is not None and np.array_equal(last_at[0][0], step2_alone),
        "FitTimeStep 5 (clamped to the last step) fits on step 2 alone")
C.check(last_at[1][0] is not None and not np.array_equal(last_at[1][0], at[0][0]) and
        last_at[1][1] is not None,
        "... and places step 0 with that fit (other coordinates than step 0's own fit)")

# The pictures: the same widgets on steps 0 and 2, one fit vs a fit per step.
view = CreateView("RenderView")
view.ViewSize = [360, 300]
pictures = {}
widgets = None
for label, reduction in (("one_fit", one), ("fit_per_step", each)):
    GetAnimationScene().AnimationTime = times[0]
    display = mce.show_gaussian_tf(reduction, view)
    if widgets is None:
        widgets = mce.auto_widgets(display, count=4, view=view, opacity=0.3)
    display.GaussianWidgets = widgets
    display.ShowWidgetLegend = 0  # the volume's colours only (the legend's shares move too)
    for t in (times[0], times[2]):
        GetAnimationScene().AnimationTime = t
        view.ViewTime = t
        Render(view)
        path = os.path.join(OUT, "%s_t%d.png" % (label, int(round(t))))
        SaveScreenshot(path, view, ImageResolution=[360, 300])
        image = mce._read_png(path)
        pictures[(label, t)] = vtk_to_numpy(image.GetPointData().GetScalars()).copy()
    Hide(reduction, view)


def changed_pixels(a, b):
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    return float(np.mean(np.abs(a - b).max(axis=-1) > 10))


one_change = changed_pixels(pictures[("one_fit", times[0])], pictures[("one_fit", times[2])])
each_change = changed_pixels(pictures[("fit_per_step", times[0])],
                             pictures[("fit_per_step", times[2])])
C.check(one_change > 0.02 and one_change > 3 * each_change,
        "the brightening changes the picture with one fit (%.1f%% of pixels) and barely with "
        "a fit per step (%.1f%%)" % (100 * one_change, 100 * each_change))
C.finish()
