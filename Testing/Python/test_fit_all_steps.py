"""One fit on all time steps, and "One time step" on the step current when it was set:
DimensionReduction's FitTime on a 3-step series of the real brain (Colin27 T1 + AAL atlas,
every 3rd voxel) whose step 1 repeats step 0 and whose step 2 is step 0 with the T1
brightened x 1.2.

Known answers (FitTime "All time steps"):
- the normalisation is that of the three steps as one volume: the intensity columns'
  offsets and scales are the mean and 1/standard deviation of the three steps' values
  (numpy, 1e-9 relative);
- the reference sample is drawn from every step: the voxels it was drawn from are the sum
  of each step's (a fit per step reports each step's own);
- steps 0 and 1 (the same voxels) get exactly the same coordinates; step 2 moves;
- the model saved from it, applied to step 0 alone, gives step 0's coordinates exactly;
- a step with other channels than step 0: an error naming it, no output.
FitTime "One time step" with FitTimeStep -1 fits on the step current when it was set
(FittedTimeStep says which) and keeps that fit when the time moves on.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
import numpy as np  # noqa: E402
from paraview.simple import OpenDataFile  # noqa: E402

C = T.Checker("test_fit_all_steps")
OUT = os.path.join(T.output_dir(), "fit_all_steps")
os.makedirs(OUT, exist_ok=True)

factors = (1.0, 1.0, 1.2)
series, times, steps, t1, aal = T.opened_brain_series(C, OUT, factors)
foreground = t1.ravel() > 0

# ---- All time steps --------------------------------------------------------------------
every = T.pca_reduction(mce, series, FitTime="All time steps")
messages = T.Messages(every)
at = [T.coordinates_at(every, t) for t in times]
C.check(all(a[0] is not None for a in at) and not messages.errors,
        "every step is placed (errors: %s)" % messages.errors)
C.check(np.array_equal(at[0][0], at[1][0]),
        "steps 0 and 1 (the same voxels) get exactly the same coordinates")
moved = np.linalg.norm(at[2][0] - at[0][0], axis=1)[foreground]
C.check(float(np.median(moved)) > 0.05,
        "step 2 (T1 x 1.2) moves: median shift %.3f of the foreground" % float(np.median(moved)))
C.check(all(s is not None and "all time steps" in s[0] for _, s in at),
        "every step names the fit of all time steps as its model: %s" % ([s for _, s in at],))

model_path = mce.save_model(every, os.path.join(OUT, "all_steps.mcvmodel"))
info = mce.read_model(model_path)
C.check(info["fit"]["fittedOn"] == "all 3 time steps", "the model says what it was fitted on: %r"
        % info["fit"]["fittedOn"])
names = info["features"]["names"]
for channel, values in (("ch2", [t1 * f for f in factors]), ("aal", [aal] * 3)):
    column = next(i for i, n in enumerate(names) if n.startswith(channel) and "ntensity" in n)
    stacked = np.concatenate([v.ravel().astype(np.float64) for v in values])
    mean, sd = float(stacked.mean()), float(stacked.std())
    offset = info["features"]["offset"][column]
    scale = info["features"]["scale"][column]
    C.check(abs(offset - mean) <= 1e-9 * abs(mean) and abs(scale * sd - 1.0) <= 1e-9,
            "%s: the normalisation of the three steps as one volume (offset %.9g vs mean %.9g, "
            "scale %.9g vs 1/sd %.9g)" % (names[column], offset, mean, scale, 1.0 / sd))

each = T.pca_reduction(mce, series)
per_step = []
for t in times:
    each.UpdatePipeline(t)
    each.UpdatePropertyInformation()
    per_step.append(int(each.GetPropertyValue("NumberOfSampledVoxels")))
C.check(info["fit"]["sampledVoxels"] == sum(per_step),
        "the sample is drawn from the voxels of every step: %d = %s"
        % (info["fit"]["sampledVoxels"], " + ".join(str(v) for v in per_step)))

applied = T.pca_reduction(mce, OpenDataFile(steps[0]), ModelFile=model_path)
applied_at, _ = T.coordinates_at(applied, 0.0)
C.check(applied_at is not None and np.array_equal(applied_at, at[0][0]),
        "the saved model applied to step 0 alone gives step 0's coordinates exactly")

# Steps with other channels cannot share a fit.
odd = [steps[0], T.write_vti(os.path.join(OUT, "odd_1.vti"), [("ch2", t1), ("atlas", aal)])]
odd_series = OpenDataFile(odd)
odd_series.UpdatePipelineInformation()
odd_reduction = T.pca_reduction(mce, odd_series, FitTime="All time steps")
odd_messages = T.Messages(odd_reduction)
odd_at, _ = T.coordinates_at(odd_reduction, list(odd_series.TimestepValues)[0])
C.check(odd_at is None and odd_messages.any_error("time step 1", "other channels", "step 0"),
        "a step with other channels: no output and an error naming the step: %s"
        % odd_messages.errors)

# ---- One time step, the current one ----------------------------------------------------
current = T.pca_reduction(mce, series, FitTime="One time step")
C.check(int(current.GetPropertyValue("FitTimeStep")) == -1, "FitTimeStep defaults to -1 (current)")
cur_at1, cur_src = T.coordinates_at(current, times[1])
current.UpdatePropertyInformation()
C.check(int(current.GetPropertyValue("FittedTimeStep")) == 1,
        "set at time %g, the fit is on step 1 (FittedTimeStep %s)"
        % (times[1], current.GetPropertyValue("FittedTimeStep")))
cur_at2, cur_src2 = T.coordinates_at(current, times[2])
current.UpdatePropertyInformation()
C.check(int(current.GetPropertyValue("FittedTimeStep")) == 1 and cur_src2 is not None and
        ("fit of time %g" % times[1]) in cur_src2[0],
        "moving on to step 2 keeps the fit of step 1: %s" % (cur_src2,))
one_at_1 = T.pca_reduction(mce, series, FitTime="One time step", FitTimeStep=1)
explicit, _ = T.coordinates_at(one_at_1, times[2])
C.check(cur_at2 is not None and np.array_equal(cur_at2, explicit),
        "... the same coordinates as FitTimeStep 1")
C.finish()
