"""Python state files and traces load the plugin and keep what the helpers set, hidden
Gaussian widgets included.

  pvbatch state_replay_check.py --record DIR
      a scene of the plugin: a synthetic volume (Wavelet; ReducedCoordinates = the voxel
      position / 10) as a Gaussian TF Volume with 3 widgets, show_gaussian_tf's settings
      not the defaults (Maximum Intensity, Per voxel), widget 2 hidden as the editor hides
      it (opacity 0 in GaussianWidgets, the opacity it gets back in GaussianWidgetsHidden),
      and its reduced domain (ReducedDomain, a filter of the plugin). Writes
      DIR/state.py (mce.save_state), DIR/smstate.py (ParaView's own
      paraview.smstate.get_state, with the package imported), DIR/state.pvsm, DIR/trace.py
      (a trace of the same scene built from scratch) and the picture DIR/recorded.png;
      checks that the Python files load the plugin (server side first) right after
      `from paraview.simple import *` and set GaussianWidgetsHidden, and that the trace sets
      show_gaussian_tf's settings.
  pvbatch state_replay_check.py --replay DIR FILE
      in a fresh process WITHOUT the plugin loaded: runs DIR/FILE (a Python state or the
      trace), which must load the plugin itself; the display has the recorded widgets,
      hidden list, blend and classification, and the picture equals DIR/recorded.png.
Driver: record_replay.sh (CTest pvbatch.test_state_replay).
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple, smtrace  # noqa: E402

VIEW_SIZE = [300, 300]
WIDGETS = [0.0, 0.0, 0.0, 0.4, 1.0, 0.2, 0.1, 0.9,
           0.6, 0.6, 0.0, 0.3, 0.1, 0.9, 0.2, 0.0,     # hidden: drawn with opacity 0
           -0.6, 0.5, 0.2, 0.35, 0.2, 0.3, 1.0, 0.8]
HIDDEN = [-1.0, 0.7, -1.0]   # widget 2 gets opacity 0.7 back when shown
def setting(display, name):
    """An enumeration or string property's text."""
    from paraview import servermanager

    return servermanager.vtkSMPropertyHelper(display.SMProxy, name).GetAsString()


SETTINGS = dict(GaussianBlendMode="Maximum Intensity", Classification="Per voxel",
                CoordinateArray="ReducedCoordinates")


def scene(mce):
    volume = simple.Wavelet(registrationName="Volume", WholeExtent=[-10, 10, -10, 10, -8, 8])
    coords = simple.Calculator(registrationName="Coordinates", Input=volume,
                               ResultArrayName="ReducedCoordinates", ResultArrayType="Float",
                               Function="0.1*coords")
    view = simple.CreateView("RenderView")
    simple.SetActiveView(view)
    view.ViewSize = VIEW_SIZE
    view.OrientationAxesVisibility = 0
    display = mce.show_gaussian_tf(coords, view, widgets=WIDGETS, blend="Maximum Intensity",
                                   classification="Per voxel")
    # As the Gaussian Widgets editor hides a widget (its trace scope).
    with mce._common._TracedProperties(display):
        display.GaussianWidgetsHidden = HIDDEN
    mce.reduced_domain_filter(display)
    view.CameraPosition = [30, -40, 50]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 0, 1]
    simple.Render(view)
    return display, view


def record(C, out):
    mce = T.load_plugin(globals())
    from paraview import smstate

    smtrace.start_trace()
    display, view = scene(mce)
    trace = smtrace.stop_trace()
    with open(os.path.join(out, "trace.py"), "w") as f:
        f.write(trace)
    simple.SaveScreenshot(os.path.join(out, "recorded.png"), view, ImageResolution=VIEW_SIZE)
    mce.save_state(os.path.join(out, "state.py"))
    with open(os.path.join(out, "smstate.py"), "w") as f:
        f.write(smstate.get_state())
    mce.save_state(os.path.join(out, "state.pvsm"))
    recorded = {"widgets": [float(v) for v in display.GaussianWidgets],
                "hidden": [float(v) for v in display.GaussianWidgetsHidden]}
    recorded.update({k: setting(display, k) for k in SETTINGS})
    with open(os.path.join(out, "recorded.json"), "w") as f:
        json.dump(recorded, f)
    C.check(recorded["widgets"] == WIDGETS and recorded["hidden"] == HIDDEN and
            all(recorded[k] == v for k, v in SETTINGS.items()), "the scene: %s" % recorded)

    for name in ("state.py", "smstate.py", "trace.py"):
        with open(os.path.join(out, name)) as f:
            lines = f.read().splitlines()
        imported = lines.index("from paraview.simple import *") \
            if "from paraview.simple import *" in lines else None
        loads = [i for i, line in enumerate(lines) if line.startswith("LoadPlugin(")]
        created = [i for i, line in enumerate(lines)
                   if "= Calculator(" in line or "= Wavelet(" in line]
        C.check(imported is not None and len(loads) == 1 and created and
                imported < loads[0] < created[0] and
                lines[loads[0]].endswith("MultichannelExplorer.so', remote=False, "
                                         "ns=globals())"),
                "%s loads the plugin after `from paraview.simple import *` (line %s), before "
                "anything is created (line %s): %s"
                % (name, imported is not None and imported + 1, created and created[0] + 1,
                   [lines[i] for i in loads]))
        C.check(any(".GaussianWidgetsHidden = [-1.0, 0.7, -1.0]" in line for line in lines),
                "%s sets GaussianWidgetsHidden" % name)
        for key, value in SETTINGS.items():
            if value != "ReducedCoordinates":  # the default: a state may leave it out
                C.check(any(".%s = '%s'" % (key, value) in line for line in lines),
                        "%s sets %s = %r" % (name, key, value))
    with open(os.path.join(out, "state.pvsm")) as f:
        pvsm = f.read()
    C.check('name="GaussianWidgetsHidden"' in pvsm and "ReducedDomain" in pvsm,
            "state.pvsm holds GaussianWidgetsHidden and the ReducedDomain (no plugin: "
            "ParaView 5.11 records none in a .pvsm)")


def replay(C, out, name):
    from paraview import servermanager

    C.check(not hasattr(simple, "DimensionReduction"),
            "%s: the plugin is not loaded before the file runs" % name)
    namespace = {"__name__": "__state__"}
    path = os.path.join(out, name)
    with open(path) as f:
        exec(compile(f.read(), path, "exec"), namespace)
    C.check("DimensionReduction" in namespace, "%s loaded the plugin" % name)
    with open(os.path.join(out, "recorded.json")) as f:
        recorded = json.load(f)
    coords = simple.FindSource("Coordinates")
    views = [v for v in simple.GetViews() if v.GetXMLName() == "RenderView"]
    display = None
    for view in views:
        rep = servermanager.GetRepresentation(coords, view) if coords else None
        if rep is not None and rep.Visibility:
            display, shown_in = rep, view
    if not C.check(display is not None, "%s: the volume is shown" % name):
        return
    got = {"widgets": [float(v) for v in display.GaussianWidgets],
           "hidden": [float(v) for v in display.GaussianWidgetsHidden]}
    got.update({k: setting(display, k) for k in SETTINGS})
    C.check(got == recorded, "%s: the display's widgets, hidden widgets, blend, "
            "classification and coordinates as recorded (%s)" % (name, got))
    C.check(any(p.GetXMLName() == "ReducedDomain" for p in simple.GetSources().values()),
            "%s: the ReducedDomain is back" % name)
    shown_in.ViewSize = VIEW_SIZE
    simple.Render(shown_in)
    replayed = os.path.join(out, "replayed_%s.png" % name.replace(".", "_"))
    simple.SaveScreenshot(replayed, shown_in, ImageResolution=VIEW_SIZE)
    diff = T.picture_difference(os.path.join(out, "recorded.png"), replayed)
    C.check(diff is not None and diff[1] <= 0.005 and diff[2] > 0.05,
            "%s: the recorded picture (%s)" % (name, "max channel difference %d, %.3f%% of "
            "pixels above 12, %.1f%% not background" % (diff[0], 100 * diff[1], 100 * diff[2])
            if diff else "a picture of another size"))


def main():
    parser = argparse.ArgumentParser()
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--record", metavar="DIR")
    mode.add_argument("--replay", nargs=2, metavar=("DIR", "FILE"))
    args = parser.parse_args()
    C = T.Checker("state_replay_check (%s)" % ("record" if args.record else
                                               "replay " + args.replay[1]))
    if args.record:
        os.makedirs(args.record, exist_ok=True)
        record(C, args.record)
    else:
        replay(C, *args.replay)
    C.finish()


main()
