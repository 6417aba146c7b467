"""A ParaView trace of the README workflow replays to the same picture.

  pvbatch trace_replay_check.py --record DIR
      records a trace (smtrace) of the workflow done with the Python helpers: the real
      brain (every 3rd voxel), reduce_multichannel PCA 6D, show_gaussian_tf,
      auto_widgets, apply_best_viewpoint; saves the picture (DIR/recorded.png) and the
      trace (DIR/trace.py), and checks that the trace loads the plugin and sets what the
      helpers set (FeatureSet, GaussianWidgets, OpacitySource).
  pvbatch trace_replay_check.py --replay DIR
      in a fresh process WITHOUT the plugin loaded (no PV_PLUGIN_PATH): runs DIR/trace.py,
      which must load the plugin itself, and compares its picture with DIR/recorded.png
      (within a small pixel tolerance).
Driver: record_replay.sh (CTest pvbatch.test_trace_replay).
"""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple, smtrace  # noqa: E402

VIEW_SIZE = [400, 400]
DIFFERING_FRACTION = 0.005


def record(C, out):
    mce = T.load_plugin(globals())
    smtrace.start_trace()
    # Properties set from a script outside a trace scope are not traced (ParaView's rule):
    # brain_subset gives them to the constructors, so they are.
    volume = T.brain_subset(3)
    feats, red = mce.reduce_multichannel(volume, "PCA", "6D", output_dimension=3,
                                         ReferenceSampleSize=3000, RandomSeed=7)
    view = simple.CreateView("RenderView")
    simple.SetActiveView(view)
    view.ViewSize = VIEW_SIZE
    display = mce.show_gaussian_tf(red, view)
    mce.auto_widgets(display, 3, seed=1)
    mce.apply_best_viewpoint(red, view)
    simple.Render(view)
    text = smtrace.stop_trace()
    simple.SaveScreenshot(os.path.join(out, "recorded.png"), view, ImageResolution=VIEW_SIZE)
    with open(os.path.join(out, "trace.py"), "w") as f:
        f.write(text)
    load = [line for line in text.splitlines() if line.startswith("LoadPlugin(")]
    C.check(len(load) == 1 and "MultichannelExplorer.so', remote=False, ns=globals())" in load[0],
            "the trace loads the plugin (%s)" % load)
    lines = text.splitlines()
    created = [i for i, line in enumerate(lines) if re.match(r"^\w+ = \w+\(", line)]
    loaded = [i for i, line in enumerate(lines) if line.startswith("LoadPlugin(")]
    imported = lines.index("from paraview.simple import *")
    C.check(loaded and created and imported < loaded[0] < created[0],
            "the LoadPlugin line comes after the import (line %d), before anything is "
            "created (line %s): line %s" % (imported + 1, created and created[0] + 1,
                                            loaded and loaded[0] + 1))
    for name in (".FeatureSet = '6D'", ".GaussianWidgets = [", ".OpacitySource = ",
                 ".RandomSeed = 7", ".ReferenceSampleSize = 3000", ".SampleRateI = 3"):
        C.check(name in text, "the trace sets %s" % name.strip(". =["))


def replay(C, out):
    from paraview import simple as pvs

    C.check(not hasattr(pvs, "DimensionReduction"),
            "replay: the plugin is not loaded before the trace runs")
    namespace = {"__name__": "__trace__"}
    with open(os.path.join(out, "trace.py")) as f:
        code = compile(f.read(), os.path.join(out, "trace.py"), "exec")
    exec(code, namespace)
    view = pvs.GetActiveView()
    view.ViewSize = VIEW_SIZE
    pvs.Render(view)
    replayed = os.path.join(out, "replayed.png")
    pvs.SaveScreenshot(replayed, view, ImageResolution=VIEW_SIZE)
    diff = T.picture_difference(os.path.join(out, "recorded.png"), replayed)
    C.check(diff is not None and diff[1] <= DIFFERING_FRACTION and diff[2] > 0.05,
            "the replayed trace draws the recorded picture: %s"
            % ("max channel difference %d, %.3f%% of pixels above %d, %.1f%% of pixels not background"
               % (diff[0], 100 * diff[1], T.PIXEL_TOLERANCE, 100 * diff[2]) if diff
               else "a picture of another size"))


def main():
    parser = argparse.ArgumentParser()
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--record", metavar="DIR")
    mode.add_argument("--replay", metavar="DIR")
    args = parser.parse_args()
    C = T.Checker("trace_replay_check (%s)" % ("record" if args.record else "replay"))
    out = args.record or args.replay
    os.makedirs(out, exist_ok=True)
    if args.record:
        record(C, out)
    else:
        replay(C, out)
    C.finish()


if __name__ == "__main__":
    main()
