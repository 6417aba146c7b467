"""Widget values from Python that are no widget (nan, inf, a centre beyond 1e30, sigma beyond
1e6 x the reduced domain's size) are errors naming the widget and the field, never values
the display takes silently: show_gaussian_tf, add_widget_at and check_widget_values on a
small volume of known reduced coordinates (each voxel's coordinates its own (i, j, k) / 10,
so the domain's size is 0.9 along each axis); and a state file whose widget list holds nan,
inf, 1e31 or text (ParaView's loader would read 0.0) refused by load_state, naming the file,
(and, loaded with ParaView's own simple.LoadState, reported by the plugin's check of loaded
states: vtkSMGaussianWidgetsStateCheck),
the widget and the field.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_widget_values")

import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402

image = vtkImageData()
image.SetDimensions(10, 10, 10)
k, j, i = np.meshgrid(range(10), range(10), range(10), indexing="ij")
xyz = (np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1) / 10.0).astype(np.float32)
array = numpy_to_vtk(xyz, deep=True)
array.SetName("ReducedCoordinates")
image.GetPointData().AddArray(array)
source = simple.PVTrivialProducer()
source.GetClientSideObject().SetOutput(image)
source.UpdatePipeline()
view = simple.CreateView("RenderView")

GOOD = (0.4, 0.4, 0.4, 0.1, 1, 0, 0, 1)


def refused(widgets, words, label):
    try:
        mce.show_gaussian_tf(source, view, widgets=widgets)
    except ValueError as exc:
        text = str(exc)
        return C.check(all(w in text for w in words), "%s: %s" % (label, text))
    return C.check(False, "%s: accepted" % label)


display = mce.show_gaussian_tf(source, view, widgets=[GOOD])
C.check([float(v) for v in display.GaussianWidgets] == [float(v) for v in GOOD],
        "a good widget is set as given")
refused([GOOD, (0.1, 0.2, 0.3, float("nan"), 0, 1, 0, 1)], ["widget 1", "sigma", "nan"],
        "nan sigma")
refused([(float("inf"), 0.2, 0.3, 0.1, 0, 1, 0, 1)], ["widget 0", "cx", "inf"], "inf centre")
refused([GOOD, GOOD, (0.1, -2e30, 0.3, 0.1, 0, 1, 0, 1)], ["widget 2", "cy", "1e+30"],
        "centre beyond 1e30")
refused([(0.1, 0.2, 0.3, 0.9e6 * 1.01, 0, 1, 0, 1)], ["widget 0", "sigma", "domain's size 0.9"],
        "sigma beyond 1e6 x the domain's size")
refused([(0.1, 0.2, 0.3, 0.1, 0, float("nan"), 0, 1)], ["widget 0", "g"], "nan colour")
refused([0.1, 0.2, 0.3], ["3 values", "multiple of 8"], "a list not of 8-value widgets")
C.check(mce.check_widget_values(list(GOOD) + [0.1, 0.2, 0.3, 0.85e6, 0, 0, 1, 0.5],
                                domain_size=0.9) is not None,
        "sigma just below 1e6 x the domain's size is accepted")
display = mce.show_gaussian_tf(source, view, widgets=[GOOD])
try:
    mce.add_widget_at(display, (0.5, float("nan"), 0.5))
    C.check(False, "add_widget_at with a nan coordinate: accepted")
except ValueError as exc:
    C.check("widget 1's cy" in str(exc), "add_widget_at, nan (the display's second widget): %s"
            % exc)
C.check(len(display.GaussianWidgets) == 8, "the refused widget was not added")
added = mce.add_widget_at(display, (0.5, 0.5, 0.5))
C.check(len(display.GaussianWidgets) == 16 and math.isclose(added[3], 0.05 * 0.9, rel_tol=1e-6),
        "a good widget is added (sigma %g = 5%% of the domain's size)" % added[3])

# A state file: saved by ParaView with a good widget list, then one value written as "nan"
# (as a hand edit or another tool would): ParaView's loader would read 0.0.
work = os.path.join(T.output_dir(), "widget_values")
os.makedirs(work, exist_ok=True)
good_state = os.path.join(work, "good.pvsm")
simple.SaveState(good_state)
with open(good_state) as f:
    text = f.read()
C.check(mce.check_state_file(good_state) >= 1, "a saved state's widget lists pass the check")
import re  # noqa: E402

match = re.search(r'(<Property name="GaussianWidgets"[^>]*>\s*(?:<Element[^>]*/>\s*){9})'
                  r'<Element index="9" value="[^"]*"', text)
if C.check(match is not None, "the saved state holds the widgets' elements"):
    for bad, words in (("nan", ["widget 1's cy", "is nan"]), ("inf", ["widget 1's cy", "inf"]),
                       ("1e31", ["widget 1's centre cy"]), ("abc", ["widget 1's cy", "not a number"])):
        edited = text[:match.end()].rsplit('value="', 1)[0] + 'value="%s"' % bad + \
            text[match.end():]
        path = os.path.join(work, "bad_%s.pvsm" % bad)
        with open(path, "w") as f:
            f.write(edited)
        try:
            mce.load_state(path)
            C.check(False, "state file with %s: loaded" % bad)
        except ValueError as exc:
            C.check(all(w in str(exc) for w in words) and "bad_%s.pvsm" % bad in str(exc),
                    "state file with %s refused: %s" % (bad, exc))
    # ParaView's own loader (File > Load State, simple.LoadState) reads the "nan" as 0.0;
    # the plugin's check of loaded states says so, naming the proxy, widget and field.
    from paraview import servermanager  # noqa: E402
    from vtkmodules.util.misc import calldata_type  # noqa: E402
    from vtkmodules.util.vtkConstants import VTK_STRING  # noqa: E402

    loader_errors = []

    @calldata_type(VTK_STRING)
    def on_error(caller, event, text):
        loader_errors.append(str(text))

    manager = servermanager.vtkSMProxyManager.GetProxyManager()
    observer = manager.AddObserver("ErrorEvent", on_error)
    for bad, words in (("nan", ["widget 1's cy", "'nan'", "not a finite number"]),
                       ("1e31", ["widget 1's centre cy", "beyond"])):
        del loader_errors[:]
        simple.LoadState(os.path.join(work, "bad_%s.pvsm" % bad))
        C.check(any(all(w in e for w in words) and "GaussianWidgets of" in e
                    for e in loader_errors),
                "simple.LoadState of the state with %s: an error naming the widget and field: %s"
                % (bad, loader_errors))
    del loader_errors[:]
    simple.LoadState(good_state)
    C.check(not loader_errors, "simple.LoadState of the good state: no error (%s)" % loader_errors)
    manager.RemoveObserver(observer)
C.finish()
