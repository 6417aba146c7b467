"""edit_widget changes one Gaussian widget of a "Gaussian TF Volume" display, picked by
name or index, and nothing else, in one property update:

* a shown widget's colour and opacity, by name: those four numbers change, the other
  widgets' do not; observers of GaussianWidgets see one modification;
* a hidden widget (opacity 0 in GaussianWidgets, the one it gets back in
  GaussianWidgetsHidden) given an opacity stays hidden and gets that one back when shown
  (by a negative index); with no widget hidden the hidden list is empty again;
* hiding a shown widget keeps its opacity; a new name lands in GaussianWidgetNames; a
  centre of 2 numbers gets cz = 0; a source shown as one in a view is taken too;
* show_widgets shows the widgets named or indexed (a hidden one at its kept opacity) and
  hides the others keeping theirs, in one modification; all shown again as they were;
* bad input (unknown or shared name, index past the end, opacity 1.5, a colour of 2
  numbers, sigma 0, a display of another representation) is a ValueError and leaves the
  widgets as they were.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())

C = T.Checker("test_edit_widget")

wavelet = Wavelet(WholeExtent=[-10, 10, -10, 10, -10, 10])
coords = Calculator(Input=wavelet, ResultArrayName="ReducedCoordinates",
                    ResultArrayType="Float", Function="coords")
view = simple.GetActiveViewOrCreate("RenderView")
left = [-5.0, 0.0, 0.0, 2.0, 0.0, 0.0, 1.0, 0.5]
right = [5.0, 0.0, 0.0, 2.0, 0.0, 1.0, 0.0, 0.4]
deep = [0.0, 0.0, -5.0, 3.0, 1.0, 1.0, 0.0, 0.0]    # hidden: shown again at 0.3
display = mce.show_gaussian_tf(coords, view, widgets=left + right + deep)
display.GaussianWidgetNames = ["left", "right", "deep"]
display.GaussianWidgetsHidden = [-1.0, -1.0, 0.3]
modified = []
display.SMProxy.GetProperty("GaussianWidgets").AddObserver(
    "ModifiedEvent", lambda *unused: modified.append(1))


def widgets():
    return [float(v) for v in display.GaussianWidgets]


def hidden():
    return [float(v) for v in display.GaussianWidgetsHidden]


got = mce.edit_widget(display, "right", color=(1, 0, 0), opacity=0.2)
expect = right[:4] + [1.0, 0.0, 0.0, 0.2]
C.check(got == expect and widgets() == left + expect + deep,
        "by name: only the widget's colour and opacity change: %s" % widgets()[8:16])
C.check(len(modified) == 1, "observers see one modification (%d)" % len(modified))
C.check(hidden() == [-1.0, -1.0, 0.3], "the hidden list is kept: %s" % hidden())

mce.edit_widget(display, "deep", opacity=0.6)
C.check(widgets()[23] == 0.0 and hidden() == [-1.0, -1.0, 0.6],
        "a hidden widget given an opacity stays hidden and keeps it: %s, %s"
        % (widgets()[23], hidden()))
got = mce.edit_widget(display, -1, shown=True)
C.check(got == deep[:7] + [0.6] and widgets()[16:] == got and hidden() == [],
        "shown again (index -1) at the kept opacity, no widget hidden: %s, %s"
        % (widgets()[16:], hidden()))

mce.edit_widget(display, 0, shown=False, name="gone")
C.check(widgets()[:8] == left[:7] + [0.0] and hidden() == [0.5, -1.0, -1.0],
        "hidden: opacity 0, the 0.5 kept for showing: %s, %s" % (widgets()[:8], hidden()))
C.check(list(display.GaussianWidgetNames) == ["gone", "right", "deep"],
        "renamed: %s" % list(display.GaussianWidgetNames))
got = mce.edit_widget(coords, "right", center=(1.5, -2.5), sigma=0.75, view=view)
C.check(got[:4] == [1.5, -2.5, 0.0, 0.75],
        "a source shown in the view, a 2-number centre (cz 0) and sigma: %s" % got[:4])

# show_widgets: those named shown (a hidden one at its kept opacity), the rest hidden
# with theirs kept, in one modification; then all shown again as they were.
count = len(modified)
start, start_hidden = widgets(), hidden()
C.check(mce.show_widgets(display, ["gone", 2]) == [0, 2] and len(modified) == count + 1,
        "show_widgets(['gone', 2]): widgets 0 and 2 shown, one modification")
C.check([widgets()[8 * i + 7] for i in range(3)] == [0.5, 0.0, 0.6] and
        hidden() == [-1.0, 0.2, -1.0],
        "... widget 0 back at 0.5, widget 1 hidden keeping 0.2: %s, %s"
        % ([widgets()[8 * i + 7] for i in range(3)], hidden()))
mce.show_widgets(display, range(3))
C.check([widgets()[8 * i + 7] for i in range(3)] == [0.5, 0.2, 0.6] and hidden() == [],
        "show_widgets(range(3)): every widget at its opacity, none hidden: %s"
        % [widgets()[8 * i + 7] for i in range(3)])
mce.show_widgets(display, [])
C.check(widgets()[7::8] == [0.0, 0.0, 0.0] and hidden() == [0.5, 0.2, 0.6],
        "show_widgets([]): all hidden, each opacity kept: %s" % hidden())
mce.show_widgets(display, "right")
C.check(widgets()[7::8] == [0.0, 0.2, 0.0] and widgets()[:7] == start[:7],
        "show_widgets('right'): that one alone, centres and colours untouched")
display.GaussianWidgetsHidden = start_hidden
display.GaussianWidgets = start

before, before_hidden, count = widgets(), hidden(), len(modified)
display.GaussianWidgetNames = ["gone", "right", "right"]
for which, args, words in [
        ("nope", {}, "no widget is named 'nope'; the widgets are 0 'gone', 1 'right'"),
        ("right", {}, "2 widgets are named 'right' (widgets 1, 2)"),
        (3, {}, "widget 3 does not exist: the display has 3 widgets"),
        (1, {"opacity": 1.5}, "opacity is in [0, 1]"),
        (1, {"color": (1, 0)}, "colour is 3 numbers in [0, 1]"),
        (1, {"sigma": 0}, "sigma is positive")]:
    try:
        mce.edit_widget(display, which, **args)
        message = "no error"
    except ValueError as error:
        message = str(error)
    C.check(words in message, "edit_widget(%r, %s) refused: %s" % (which, args, message))
try:
    mce.show_widgets(display, [0, "nope"])
    message = "no error"
except ValueError as error:
    message = str(error)
C.check("no widget is named 'nope'" in message, "show_widgets([0, 'nope']) refused: %s"
        % message)
C.check(widgets() == before and hidden() == before_hidden and len(modified) == count,
        "the refused edits changed nothing")
outline = Show(wavelet, view)
outline.SetRepresentationType("Outline")
try:
    mce.edit_widget(outline, 0)
    message = "no error"
except ValueError as error:
    message = str(error)
C.check("Gaussian TF Volume" in message, "an Outline display is refused: %s" % message)
C.finish()
