"""Every time step of a multichannel series rendered with ONE reduction model, so that a
colour means the same tissue in every frame.

    xvfb-run -a pvbatch Examples/time_series.py --input FILE [FILE ...] --output DIR
        [--model FILE.mcvmodel | --fit-step N | --fit-all] [--method PCA --features 6D]
        [--widgets 4] [--camera fixed|follow] [--turn-frames 6] [--size W H]
        [--movie NAME.ogv | --movie none] [--plugin PATH]

Input: one file with time steps (an ImageJ hyperstack with frames, an OME-TIFF or OME-Zarr
with t, a ParaView file series) or one file per time step (listed in order).
The reduction: --model applies a saved model (multichannel_explorer.save_model, or File >
Save Data on a DimensionReduction's Spectrum output) to every step; without one, the steps
are reduced with DimensionReduction's FitTime "One time step" on --fit-step (default 0): one
fit, every step placed with it, and the model is written as OUTPUT/model.mcvmodel; --fit-all
fits once on all steps instead (FitTime "All time steps": the normalisation of every step, the
reference sample drawn across them), for a series whose later steps hold what the first lacks.
Widgets: seeded once at the fit step (auto_widgets) and kept for every step.
Camera: "fixed" (default) looks from the best viewpoint of the fit step in every frame;
"follow" turns smoothly to each step's best viewpoint, framed on what it shows
(--turn-frames frames between steps).
Outputs (written into a staging folder and switched in when complete, batch_output.py):
  OUTPUT/frames/frame_NNNN.png one per time step (and the turning frames of "follow")
  OUTPUT/<movie>               the frames as a movie through ParaView's SaveAnimation
                               ("fixed"; "follow" writes the frames only)
  OUTPUT/model.mcvmodel        the fit's model (when no --model was given)
  OUTPUT/report.json           steps, times, out-of-model voxels per step, files
"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import batch_output as B  # noqa: E402
from example_support import (add_output_options, add_reduction_options,  # noqa: E402
                             argument_parser, load_plugin, render_view)


def parse_args(argv):
    p = argument_parser(__doc__)
    p.add_argument("--input", nargs="+", required=True, metavar="FILE",
                   help="one file with time steps, or one file per time step in order")
    add_output_options(p, None, (640, 480), "the frames, the movie and report.json")
    p.add_argument("--model", metavar="FILE.mcvmodel",
                   help="a .mcvmodel to apply to every step (none: fit one)")
    p.add_argument("--fit-step", type=int, default=0, metavar="N",
                   help="the time step the reduction is fitted on and the widgets seeded at")
    p.add_argument("--fit-all", action="store_true",
                   help="fit on all time steps (widgets are still seeded at --fit-step)")
    add_reduction_options(p, "PCA", "6D")
    p.add_argument("--camera", default="fixed", choices=("fixed", "follow"),
                   help="the fit step's best view in every frame, or a turn to each step's")
    p.add_argument("--turn-frames", type=int, default=6,
                   help='frames of each turn between steps ("follow")')
    p.add_argument("--movie", default="series.ogv",
                   help="movie file name (.ogv or .avi); none: frames only")
    return p.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    for f in args.input:
        if not os.path.exists(f):
            raise B.JobError("input not found: %s" % f)
    if args.model and not os.path.exists(args.model):
        raise B.JobError("model not found: %s" % args.model)
    from paraview import simple

    mce = load_plugin(args.plugin)
    errors = B.VtkErrors()
    run = B.RunFolder(args.output, min_free_bytes=64 << 20)
    written = []
    try:
        os.mkdir(run.path("frames"))
        source = simple.OpenDataFile(args.input if len(args.input) > 1 else args.input[0])
        if source is None:
            raise B.JobError("no reader for %s" % ", ".join(args.input))
        source.UpdatePipelineInformation()
        times = list(getattr(source, "TimestepValues", []) or [0.0])
        if isinstance(times, float):
            times = [times]
        if not 0 <= args.fit_step < len(times):
            raise B.JobError("--fit-step %d: the input has %d time step(s), 0 to %d"
                             % (args.fit_step, len(times), len(times) - 1))
        fit_step = args.fit_step
        if args.model:
            mce.read_model(args.model)  # a clear error before anything runs
            _, reduction = mce.reduce_multichannel(source, model=os.path.abspath(args.model))
        else:
            _, reduction = mce.reduce_multichannel(
                source, args.method, args.features, ReferenceSampleSize=args.reference_size)
            reduction.FitTime = "All time steps" if args.fit_all else "One time step"
            reduction.FitTimeStep = fit_step

        scene = simple.GetAnimationScene()
        scene.UpdateAnimationUsingDataTimeSteps()
        view = render_view(args.size)

        def at(step):
            scene.AnimationTime = times[step]
            view.ViewTime = times[step]
            reduction.UpdatePipeline(times[step])
            problems = errors.take()
            if problems:
                raise B.JobError("time step %d: %s" % (step, "; ".join(problems[:3])))

        at(fit_step)
        display = mce.show_gaussian_tf(reduction, view)
        widgets = mce.auto_widgets(display, args.widgets, view=view, opacity=args.widget_opacity)
        if not args.model:
            mce.save_model(reduction, run.path("model.mcvmodel"))
            written.append("model.mcvmodel")
        best = mce.apply_best_viewpoint(reduction, view, disambiguate=True)
        if not best.valid:
            raise B.JobError("no best viewpoint at the fit step (the widgets' opacity is empty)")

        steps = []
        frames = []

        def save_frame(*unused):
            name = "frames/frame_%04d.png" % len(frames)
            B.checked_png(run.path(name), lambda tmp: simple.SaveScreenshot(
                tmp, view, ImageResolution=list(args.size)), args.size)
            frames.append(name)
            written.append(name)
            return name

        for step, t in enumerate(times):
            at(step)
            if args.camera == "follow" and step > 0:
                # The step's best view (computed without moving the camera), then a smooth
                # turn there, every intermediate frame saved.
                goal = mce.best_viewpoint_filter(reduction, view)
                goal.UpdatePipeline(t)
                goal.UpdatePropertyInformation()
                direction = [float(v) for v in goal.GetPropertyValue("BestViewDirection")]
                current = [float(f) - float(p) for f, p in zip(view.CameraFocalPoint,
                                                                 view.CameraPosition)]
                if sum(a * b for a, b in zip(direction, current)) < 0:
                    direction = [-v for v in direction]  # v and -v are equally good: the nearer
                # The turn ends framed on the voxels shown, as the first frame is
                # (apply_best_viewpoint): centred, every one in view.
                up = [float(v) for v in goal.GetPropertyValue("ViewUp")]
                if sum(a * float(b) for a, b in zip(up, view.CameraViewUp)) < 0:
                    up = [-v for v in up]  # v2's sign is free: the one that rolls the least
                if bool(goal.GetPropertyValue("ViewValid")):
                    mce.turn_camera(view, None, direction, up, frames=args.turn_frames,
                                    duration=0, on_step=save_frame, fit=goal)
            else:
                simple.Render(view)
                save_frame()
            reduction.UpdatePropertyInformation()
            outside = int(reduction.GetPropertyValue("NumberOfOutOfModelVoxels"))
            steps.append(dict(step=step, time=t, frame=frames[-1], out_of_model_voxels=outside))
            print("step %d (time %g): %s, %d voxels outside the model" % (step, t, frames[-1],
                                                                           outside))

        if args.movie != "none" and args.camera == "fixed" and len(times) > 1:
            at(0)
            movie = run.path(args.movie)
            simple.SaveAnimation(movie, view, ImageResolution=list(args.size),
                                 FrameWindow=[0, len(times) - 1])
            if not os.path.exists(movie) or os.path.getsize(movie) == 0:
                raise B.JobError("the movie %s was not written" % args.movie)
            written.append(args.movie)
        report = dict(input=[os.path.abspath(f) for f in args.input], steps=steps,
                      model=os.path.abspath(args.model) if args.model else "model.mcvmodel",
                      fit_step=None if args.model else fit_step,
                      fit=("model" if args.model else "all time steps" if args.fit_all
                           else "one time step"), widgets=widgets,
                      camera=args.camera, files=written + ["report.json"])
        B.write_json(run.path("report.json"), report)
        run.commit(set(written + ["report.json", "frames"]))
        print("wrote %s (%d frames)" % (args.output, len(frames)))
    except BaseException:
        run.abandon()
        raise


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except B.JobError as exc:
        print("time_series: %s" % exc, file=sys.stderr)
        sys.stdout.flush()
        os._exit(1)
    sys.stdout.flush()
    os._exit(0)
