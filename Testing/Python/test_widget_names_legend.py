"""Widget names, the widget legend and the probe's atlas labels, on the real brain.

Chain: Colin27 T1 + AAL + Brodmann (aal.nii.txt beside aal.nii.gz) -> MergeChannels ->
MultichannelFeatures -> DimensionReduction (defaults) -> "Gaussian TF Volume" ->
auto_widgets(4). Known answers:
- widget_names on a hand-made sample: a widget whose points are 2/3 AAL label 1 is
  "Precentral_L"; one whose T1 mean lies far above the sample's is "ch2 bright", one
  near it "ch2 mid"; two with the same name get their medians (of the channel that sets
  each apart when the name is a label's or an atlas's);
- on the brain: 4 names, none empty, all different, in GaussianWidgetNames;
- the legend (GaussianWidgetLegend, what the view shows) has one row per drawn widget:
  its name and its share of the drawn voxels within its half maximum, counted here with
  numpy on the same voxels (every 7th: 7.1 M / 10^6) and formatted the same way;
  a rename shows in the legend; ShowWidgetLegend 0 removes it from the picture (the
  top-right corner changes); the camera fitted with the legend leaves its corner empty
  (and its estimate of the legend's size is the drawn one's);
- names and hidden widgets survive a state file (SaveState, ResetSession, LoadState);
- probe() of a voxel whose AAL value is 1 says aal = 1, label "Precentral_L" (the line
  of aal.nii.txt), and its other values equal the volume's at that voxel, bit for bit;
  probe_at_pixel's values equal the volume's at the voxel it picked.
Screenshots (with and without the legend) go to the test output folder.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy as np  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_widget_names_legend")
out = os.path.join(T.output_dir(), "widget_names_legend")
os.makedirs(out, exist_ok=True)

# ---- widget_names on a hand-made sample -------------------------------------------------
columns = {
    "SeededWidget": [(w,) for w in (0, 0, 0, 1, 1, 1, 2, 2, 3, 3)],
    "aal": [(v,) for v in (1, 1, 0, 0, 0, 0, 0, 0, 0, 0)],
    "ch2": [(v,) for v in (10.5, 12.5, 11.5, 200.5, 210.5, 205.5, 100.5, 101.5, 190.5, 199.5)],
}
names = mce.widget_names(columns, 4, {"aal": {1: "Precentral_L"}})
C.check(names == ["Precentral_L", "ch2 bright ~206", "outside aal", "ch2 bright ~200"],
        "widget_names: an atlas label, a bright T1 class, a mid one all outside the atlas "
        "(the sample 80 %%), twins told apart by their medians: %s" % names)
without_atlas = {k: v for k, v in columns.items() if k != "aal"}
names = mce.widget_names(without_atlas, 4, {})
C.check(names[2] == "ch2 mid", "without the atlas the mid T1 class is 'ch2 mid': %s" % names)
# Region borders: widget 0's six points all on a border of the atlas (a face neighbour
# with another label), widget 1's on none; with 5 of widget 0's points read (MIN_READ) it
# is named after the borders, with 4 (one more unread) after its T1.
sample = {"SeededWidget": [(w,) for w in (0,) * 6 + (1,) * 6],
          "aal": [(v,) for v in (1, 2, 3, 4, 6, 7, 5, 5, 5, 5, 5, 5)],
          "ch2": [(v,) for v in (50.5, 52.5, 51.5, 49.5, 50.5, 51.5) + (150.5,) * 6]}
border = [True] * 5 + [None] + [False] * 6
names = mce.widget_names(sample, 2, {}, None, {"aal": border})
C.check(names == ["aal boundaries", "aal 5"],
        "widget_names with region borders read: 'aal boundaries', then a label: %s" % names)
names = mce.widget_names(sample, 2, {}, None, {"aal": [None] + border[1:]})
C.check(names == ["ch2 dark", "aal 5"],
        "4 border points read are too few (MIN_READ 5): %s" % names)
labels = {"SeededWidget": [(w,) for w in (0, 0, 1, 1, 2, 2)],
          "aal": [(v,) for v in (1, 1, 2, 2, 1, 1)]}
names = mce.widget_names(labels, 3, {"aal": {1: "Precentral_L"}})
C.check(names == ["Precentral_L 1", "aal 2", "Precentral_L 2"],
        "two widgets of one label numbered in order, a label without a table by its "
        "value: %s" % names)
labels["ch2"] = [(v,) for v in (10.5, 11.5, 100.5, 101.5, 200.5, 201.5)]
names = mce.widget_names(labels, 3, {"aal": {1: "Precentral_L"}})
C.check(names == ["Precentral_L (ch2 ~11.5)", "aal 2", "Precentral_L (ch2 ~202)"],
        "two widgets of one label told apart by their T1 medians: %s" % names)

# ---- the brain -----------------------------------------------------------------------------
T.data_file("aal.nii.txt")  # the AAL labels beside aal.nii.gz (scripts/fetch-data.sh), else SKIP
reduction, view = T.default_brain_reduction((500, 500))
view.OrientationAxesVisibility = 0
display = mce.show_gaussian_tf(reduction, view)
mce.auto_widgets(display, 4)
names = [str(n) for n in display.GaussianWidgetNames]
C.check(len(names) == 4 and all(names) and len(set(names)) == 4,
        "auto_widgets names the 4 widgets after what they select: %s" % names)

image = reduction.GetClientSideObject().GetOutputDataObject(0)
pd = image.GetPointData()
coords = np.asarray(mce.coordinate_values(pd.GetArray("ReducedCoordinates")),
                    dtype=np.float64).reshape(-1, 3)
mask = vtk_to_numpy(pd.GetArray("Foreground"))


def expected_legend(widgets, names):
    n = coords.shape[0]
    idx = np.arange(0, n, max(1, n // 1000000))
    keep = (mask[idx] != 0) & np.isfinite(coords[idx]).all(axis=1)
    sample = coords[idx][keep]
    rows = []
    for w in range(len(widgets) // 8):
        cx, cy, cz, s = widgets[8 * w:8 * w + 4]
        if not widgets[8 * w + 7] > 0:
            continue
        d2 = ((sample - np.array([cx, cy, cz])) ** 2).sum(axis=1)
        percent = 100.0 * float((d2 <= 2.0 * math.log(2.0) * s * s).sum()) / len(sample)
        name = names[w] if w < len(names) and names[w] else "Widget %d" % (w + 1)
        rows.append("%s  %s%%" % (name, ("%.1f" if percent < 10 else "%.0f") % percent))
    return "\n".join(rows)


def legend():
    simple.Render(view)
    display.UpdatePropertyInformation()
    return display.GetProperty("GaussianWidgetLegend").GetElement(0)


widgets = [float(v) for v in display.GaussianWidgets]
shown = legend()
C.check(shown == expected_legend(widgets, names) and shown.count("\n") == 2,
        "the legend: one row per drawn widget (3; the hidden one is not drawn), name and "
        "share:\n%s" % shown)
simple.SaveScreenshot(os.path.join(out, "legend.png"), view, ImageResolution=[500, 500])

renamed = ["Scalp and skull", "Grey matter", "Ventricles", "Eyes"]
display.GaussianWidgetNames = renamed
shown = legend()
C.check(shown == expected_legend(widgets, renamed) and "Grey matter" in shown,
        "a rename shows in the legend:\n%s" % shown)
display.GaussianWidgetNames = ["Scalp\nand skull", "Grey\tmatter", "Ventricles\r\n", "Eyes"]
shown = legend()
C.check(shown == expected_legend(widgets, ["Scalp and skull", "Grey matter", "Ventricles  ",
                                           "Eyes"]),
        "a line break or tab in a name is a space: still one row per widget:\n%s" % shown)
display.GaussianWidgetNames = renamed


# Many widgets: at most 16 rows (and no taller than half the view), the rest counted in one.
many = widgets + [0.0, 0.0, 0.0, 0.01, 0.5, 0.5, 0.5, 0.2] * 40
display.GaussianWidgets = many
display.GaussianWidgetNames = []
rows = legend().split("\n")
drawn = sum(1 for w in range(len(many) // 8) if many[8 * w + 7] > 0)
C.check(len(rows) <= 16 and rows[-1] == "+ %d more widgets" % (drawn - len(rows) + 1),
        "%d drawn widgets: a legend of %d rows, the last '%s'" % (drawn, len(rows), rows[-1]))
display.GaussianWidgets = widgets
display.GaussianWidgetNames = renamed

with_legend = os.path.join(out, "with_legend.png")
without = os.path.join(out, "without_legend.png")
simple.SaveScreenshot(with_legend, view, ImageResolution=[500, 500])
display.ShowWidgetLegend = 0
simple.Render(view)
simple.SaveScreenshot(without, view, ImageResolution=[500, 500])
display.ShowWidgetLegend = 1


def top_right(path):
    from vtkmodules.vtkIOImage import vtkPNGReader
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    w, h, _ = data.GetDimensions()
    pixels = vtk_to_numpy(data.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3]
    return pixels[-(h // 6):, w // 2:].astype(int)  # VTK rows start at the bottom


diff_on = np.abs(top_right(with_legend) - top_right(without)).mean()
C.check(diff_on > 3.0, "ShowWidgetLegend 0 takes the legend out of the picture (top-right "
        "corner differs by %.1f grey levels on average)" % diff_on)


def legend_box(size):
    """(width, height) in pixels of what the legend changes in a picture of `size`."""
    from vtkmodules.vtkIOImage import vtkPNGReader
    shots = []
    for shown in (1, 0):
        display.ShowWidgetLegend = shown
        path = os.path.join(out, "legend_%dx%d_%d.png" % (size[0], size[1], shown))
        simple.SaveScreenshot(path, view, ImageResolution=list(size))
        reader = vtkPNGReader()
        reader.SetFileName(path)
        reader.Update()
        shots.append(vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
                     .reshape(size[1], size[0], -1)[:, :, :3].astype(int))
    display.ShowWidgetLegend = 1
    changed = np.abs(shots[0] - shots[1]).max(axis=2) > 0
    rows, cols = np.where(changed.any(axis=1))[0], np.where(changed.any(axis=0))[0]
    return (int(cols.max() - cols.min() + 1), int(rows.max() - rows.min() + 1)) \
        if len(rows) else (0, 0)


# The legend's size follows the view's height (rows of 13 to 20 pixels): in a small frame
# it keeps to a corner instead of covering a fifth of it.
large, small = legend_box((600, 600)), legend_box((320, 240))
C.check(0 < small[1] < 0.8 * large[1] and small[1] <= 0.22 * 240 and
        0 < small[0] < 0.8 * large[0],
        "the legend (3 rows) is %d x %d pixels in a 600 x 600 picture, %d x %d in a "
        "320 x 240 one (at most 22%% of its height)" % (large + small))


# The camera's fit keeps the volume from under the legend (apply_best_viewpoint sizes the
# legend as the representation does): fitted at 320 x 240 with the legend shown, the
# picture without the legend has nothing drawn in the legend's corner; fitted without a
# legend, the volume does reach into it (the check can fail).
def corner_pixels(size, box, legend_shown):
    """Pixels drawn (not the background) in the legend's top right `box` (fractions of the
    view) of a picture of `size`, the camera fitted with the legend shown or not, the
    picture without it."""
    from vtkmodules.vtkIOImage import vtkPNGReader
    view.ViewSize = list(size)
    display.ShowWidgetLegend = legend_shown
    mce.apply_best_viewpoint(reduction, view)
    display.ShowWidgetLegend = 0
    path = os.path.join(out, "fit_%dx%d_legend%d.png" % (size[0], size[1], legend_shown))
    simple.SaveScreenshot(path, view, ImageResolution=list(size))
    display.ShowWidgetLegend = 1
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    shot = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()) \
        .reshape(size[1], size[0], -1)[:, :, :3].astype(int)
    corner = shot[size[1] - int(round(box[1] * size[1])):, size[0] - int(round(box[0] * size[0])):]
    return int((np.abs(corner - shot[0, 0]).max(axis=2) > 8).sum())


view.ViewSize = [320, 240]
estimate = mce.viewpoint._legend_fraction(view)
gap = 7  # round(13 / 2): rows of 13 pixels at 240
C.check(estimate is not None and abs(estimate[1] * 240 - gap - small[1]) <= 3 and
        abs(estimate[0] * 320 - gap - small[0]) <= 0.25 * small[0],
        "the fit's estimate of the legend (%s of 320 x 240, gap included) is the drawn "
        "one's %d x %d pixels" % (estimate and ["%.3f" % f for f in estimate], small[0],
                                  small[1]))
box = estimate or (0.0, 0.0)
under_fitted = corner_pixels((320, 240), box, 1)
under_plain = corner_pixels((320, 240), box, 0)
C.check(under_fitted == 0 and under_plain > 0,
        "fitted with the legend, nothing is drawn under it (%d pixels in its %dx%d corner); "
        "fitted without, %d are" % (under_fitted, round(box[0] * 320), round(box[1] * 240),
                                    under_plain))
view.ViewSize = [500, 500]

# ---- state file ------------------------------------------------------------------------------
hidden = [float(v) for v in display.GaussianWidgetsHidden]
state = os.path.join(out, "names.pvsm")
simple.SaveState(state)
simple.ResetSession()
simple.LoadState(state)
pxm = servermanager.ProxyManager()
loaded = None
for (name, _), proxy in pxm.GetProxiesInGroup("representations").items():
    if proxy.GetProperty("GaussianWidgetNames") is not None and len(proxy.GaussianWidgetNames):
        loaded = proxy
C.check(loaded is not None and [str(n) for n in loaded.GaussianWidgetNames] == renamed and
        [float(v) for v in loaded.GaussianWidgetsHidden] == hidden and
        [float(v) for v in loaded.GaussianWidgets] == widgets,
        "a state file keeps the names %s and the hidden widget %s"
        % (loaded and list(loaded.GaussianWidgetNames), hidden))

# ---- the probe's labels and values -----------------------------------------------------------
display = loaded
view = [v for v in simple.GetRenderViews() if display in v.Representations][0]
reduction = display.Input
reduction.UpdatePipeline()
image = reduction.GetClientSideObject().GetOutputDataObject(0)
pd = image.GetPointData()
aal = vtk_to_numpy(pd.GetArray("aal"))
first = int(np.nonzero(aal == 1)[0][0])
dims = image.GetDimensions()
voxel = (first % dims[0], (first // dims[0]) % dims[1], first // (dims[0] * dims[1]))
hit = mce.probe(display, voxel, mark=False)


def exact(hit, point_id):
    same = all(hit.channels[n] == float(pd.GetArray(n).GetTuple1(point_id))
               for n in ("ch2", "aal", "brodmann"))
    return same and list(hit.coordinates) == [float(v) for v in
                                             pd.GetArray("ReducedCoordinates").GetTuple3(point_id)]


C.check(hit.channels["aal"] == 1 and hit.labels.get("aal") == "Precentral_L" and
        "brodmann" not in hit.labels and exact(hit, first),
        "probe of voxel %s (AAL value 1): labels %s, values equal the volume's" %
        (voxel, hit.labels))
from multichannel_explorer import _gui  # noqa: E402
text = _gui.describe(hit)
C.check("Precentral_L" in text and "brodmann" in text and "NIFTI" not in text,
        "the probe's label text names the atlas label and whole channel names:\n%s" % text)
simple.ResetCamera(view)
picked = mce.probe_at_pixel(view, 250, 250, mark=False)
C.check(picked is not None and exact(picked, picked.point_id),
        "probe_at_pixel: the picked voxel %s, its values equal the volume's"
        % (picked and tuple(picked.index),))
C.finish()
