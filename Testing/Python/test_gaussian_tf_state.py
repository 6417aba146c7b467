"""A ParaView state (.pvsm) with a "Gaussian TF Volume" display saves and loads back.

SaveState, ResetSession, LoadState: the display comes back with the same representation
type, GaussianWidgets (every value), GaussianWidgetsHidden (the GUI editor's hidden
widgets), CoordinateArray and GaussianBlendMode, and renders
the same colours (red and green at the widgets' pixels) as before the reset.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_gaussian_tf_state")

N = 24
WIDGETS = [0.25, 0.5, 0.5, 0.08, 1, 0, 0, 0.9,
           0.75, 0.5, 0.5, 0.125, 0, 1, 0, 1,
           0.5, 0.9, 0.1, 0.05, 0.2, 0.4, 0.6, 0]
# The third widget hidden in the editor: opacity 0 drawn, 0.5 remembered.
HIDDEN = [-1, -1, 0.5]
state = G.output_path("gaussian_tf_state.pvsm")

wavelet = simple.Wavelet(WholeExtent=[0, N - 1, 0, N - 1, 0, N - 1])
calc = simple.Calculator(Input=wavelet, ResultArrayName="ReducedCoordinates",
                         ResultArrayType="Float", Function="coords/%d" % (N - 1))
simple.RenameSource("coords", calc)
view = G.black_view()
display = mce.show_gaussian_tf(calc, view, widgets=WIDGETS, blend="Maximum Intensity")
display.GaussianWidgetsHidden = HIDDEN
G.look_down_z(view, [0, N - 1] * 3)
red_px = G.project(view, [0.25 * (N - 1), 0.5 * (N - 1), 0.5 * (N - 1)])
green_px = G.project(view, [0.75 * (N - 1), 0.5 * (N - 1), 0.5 * (N - 1)])
before = G.Shot(view, G.output_path("gaussian_tf_state_before.png"))
colours_before = (before.rgb(red_px), before.rgb(green_px))
print("before: %s" % (colours_before,))
C.check(G.is_colour(colours_before[0], 0, 150) and G.is_colour(colours_before[1], 1, 150),
        "before saving: red and green where the widgets are %s" % (colours_before,))

simple.SaveState(state)
C.check(os.path.exists(state), "state saved (%s)" % state)
with open(state) as f:
    text = f.read()
C.check("GaussianWidgets" in text and "Gaussian TF Volume" in text,
        "the state file holds GaussianWidgets and the representation type")

camera = (list(view.CameraPosition), list(view.CameraFocalPoint), list(view.CameraViewUp),
          float(view.CameraParallelScale))
simple.ResetSession()
C.check(simple.FindSource("coords") is None, "the session was reset")

mce = T.load_plugin(globals())
simple.LoadState(state)
source = simple.FindSource("coords")
C.check(source is not None, "the source is back")
view = simple.GetActiveViewOrCreate("RenderView")
views = simple.GetViews() if hasattr(simple, "GetViews") else [view]
view = [v for v in views if v.GetXMLName() == "RenderView"][0]
display = simple.GetDisplayProperties(source, view)
values = [float(v) for v in display.GaussianWidgets]
print("loaded: %s %s %s %s" % (display.Representation, values, display.CoordinateArray,
                               display.GaussianBlendMode))
C.check(display.Representation == "Gaussian TF Volume", "representation type restored")
C.check(len(values) == len(WIDGETS) and all(abs(a - b) < 1e-12 for a, b in zip(values, WIDGETS)),
        "GaussianWidgets restored exactly (%d values)" % len(values))
hidden = [float(v) for v in display.GaussianWidgetsHidden]
C.check(hidden == HIDDEN, "GaussianWidgetsHidden restored exactly (%s)" % hidden)
C.check(display.CoordinateArray == "ReducedCoordinates", "CoordinateArray restored")
C.check(display.GaussianBlendMode == "Maximum Intensity", "GaussianBlendMode restored")

view.ViewSize = [400, 400]
view.CameraPosition, view.CameraFocalPoint, view.CameraViewUp = camera[:3]
view.CameraParallelProjection = 1
view.CameraParallelScale = camera[3]
simple.Render(view)
after = G.Shot(view, G.output_path("gaussian_tf_state_after.png"))
colours_after = (after.rgb(red_px), after.rgb(green_px))
print("after: %s" % (colours_after,))
C.check(all(abs(a - b) <= 6 for x, y in zip(colours_before, colours_after)
            for a, b in zip(x, y)),
        "the loaded state renders the same colours %s vs %s" % (colours_before, colours_after))
C.finish()
