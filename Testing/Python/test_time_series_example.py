"""Examples/time_series.py on an ImageJ hyperstack with 3 frames of the real brain (Colin27 T1
+ AAL atlas, every 3rd voxel; frame 1 repeats frame 0, frame 2 has the T1 x 1.2), written
here with tifffile as Fiji saves one.

Known answers:
- one fit (FitTime One time step): frame 1 (the same voxels) is pixel-identical to frame 0,
  frame 2 (the brightening) differs; the model is written and reads back; the movie is
  written through SaveAnimation; report.json lists every step and file;
- the same series with that model (--model): the same frames, pixel for pixel;
- --camera follow: one frame for step 0 and --turn-frames frames for each later step;
- --fit-step beyond the steps: an error, nothing written.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_time_series_example")
import numpy as np  # noqa: E402
import tifffile  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

work = os.path.join(T.output_dir(), "time_series_example")
os.makedirs(work, exist_ok=True)
brain = T.brain_arrays(("ch2", "aal"), step=3).astype(np.float32)
frames = np.stack([brain, brain, brain * np.array([1.2, 1.0], np.float32)[:, None, None, None]])
stack = os.path.join(work, "series_tzcyx.tif")
tifffile.imwrite(stack, np.ascontiguousarray(frames.transpose(0, 2, 1, 3, 4)).astype(np.uint16),
                 imagej=True, resolution=(1 / 3.0, 1 / 3.0),
                 metadata={"axes": "TZCYX", "spacing": 3.0, "unit": "um", "finterval": 60.0})


def example(output, *extra):
    return T.run_example(C, "time_series.py", [
        "--input", stack, "--output", output, "--size", "320", "240", "--widgets", "3",
        "--reference-size", "3000"] + list(extra), output, tail=1200)


def pixels(folder, name):
    image = mce._read_png(os.path.join(folder, name))
    return vtk_to_numpy(image.GetPointData().GetScalars()).astype(int)


one = os.path.join(work, "one_fit")
report = example(one)
C.check([s["step"] for s in report["steps"]] == [0, 1, 2] and
        all(os.path.exists(os.path.join(one, f)) for f in report["files"]),
        "report.json lists the 3 steps and every file it names exists: %s" % report["files"])
f0, f1, f2 = (pixels(one, "frames/frame_%04d.png" % i) for i in range(3))
changed = float(np.mean(np.abs(f2 - f0).max(axis=1) > 10))
C.check(np.array_equal(f0, f1), "frame 1 (the same voxels) is pixel-identical to frame 0")
C.check(changed > 0.01, "frame 2 (T1 x 1.2) differs from frame 0 in %.1f%% of the pixels"
        % (100 * changed))
header = mce.read_model(os.path.join(one, "model.mcvmodel"))
C.check(header["reduction"]["method"] == "PCA" and "fit" in header and
        header["fit"]["fittedOn"].startswith("time"),
        "the model reads back (PCA, fitted on %s)" % header["fit"].get("fittedOn"))
movie = os.path.join(one, "series.ogv")
C.check(os.path.exists(movie) and os.path.getsize(movie) > 1000,
        "the movie is written (%d bytes)" % (os.path.getsize(movie) if os.path.exists(movie) else 0))

again = os.path.join(work, "with_model")
example(again, "--model", os.path.join(one, "model.mcvmodel"), "--movie", "none")
C.check(all(np.array_equal(pixels(one, "frames/frame_%04d.png" % i),
                           pixels(again, "frames/frame_%04d.png" % i)) for i in range(3)),
        "with the saved model the frames are the same, pixel for pixel")

every = os.path.join(work, "fit_all")
every_report = example(every, "--fit-all", "--movie", "none")
e0, e1, e2 = (pixels(every, "frames/frame_%04d.png" % i) for i in range(3))
C.check(every_report["fit"] == "all time steps" and
        mce.read_model(os.path.join(every, "model.mcvmodel"))["fit"]["fittedOn"] ==
        "all 3 time steps",
        "--fit-all: one fit on all 3 steps (report and model say so)")
every_change = float(np.mean(np.abs(e2 - e0).max(axis=1) > 10))
C.check(np.array_equal(e0, e1) and every_change > 0.004,
        "--fit-all: frame 1 is pixel-identical to frame 0, frame 2 (T1 x 1.2) differs in "
        "%.1f%% of the pixels" % (100 * every_change))

follow = os.path.join(work, "follow")
followed = example(follow, "--camera", "follow", "--turn-frames", "3", "--movie", "none")
names = sorted(os.listdir(os.path.join(follow, "frames")))
C.check(len(names) == 1 + 2 * 3 and [s["frame"] for s in followed["steps"]][-1] ==
        "frames/frame_0006.png",
        "--camera follow: 1 + 2 x 3 frames (%d)" % len(names))

# A fit step the series does not have is an error, not a quiet other step.
missing = os.path.join(work, "fit_step_9")
plugin = ["--plugin", os.environ["MCV_PLUGIN"]] if os.environ.get("MCV_PLUGIN") else []
run = T.run_pvbatch("pvbatch", [os.path.join(T.REPO, "Examples", "time_series.py"), "--input",
                                stack, "--output", missing, "--fit-step", "9"] + plugin)
C.check(run.returncode != 0 and "--fit-step 9: the input has 3 time step(s), 0 to 2" in
        run.stdout and not os.path.exists(missing),
        "--fit-step 9 on 3 steps: exit %d, the error names the steps, no output" % run.returncode)
C.finish()
