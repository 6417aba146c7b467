"""Transfer-function files (.mcvtf: Gaussian widgets + the reduction model they live in) on
the real brain (Colin27 T1 + AAL atlas, every 3rd voxel): save_transfer_function,
load_transfer_function, apply_transfer_function.

Known answers:
- saving a display whose reduction was fitted writes the model beside the file
  (<stem>.mcvmodel) and names it relatively with its checksum; a display whose reduction
  applies a model names that model and writes none;
- loading onto another display (a reduction of the same volume with another fit) gives
  exactly the saved GaussianWidgets, GaussianWidgetsHidden and GaussianWidgetNames (the
  display's own names replaced; a file without names clears them), switches that
  reduction to the model, and its ReducedCoordinates are then the first display's, bit
  for bit;
- applied to two volumes whose lower slices are identical (the upper half of the T1 changed),
  the widgets are identical and every voxel of the unchanged slices gets the same
  coordinates, hence the same colour; on its own fit volume no voxel is out of the model;
- a ParaView state (.pvsm) and a Python state keep the ModelFile and the widgets (the
  Python state without GaussianWidgetsHidden, which ParaView leaves out of it);
- bad input: a truncated, non-JSON or future-version file, a missing model, a model with
  another checksum, NaN widget values, a volume without a channel of the model: ValueError
  naming the file (or the channel), and nothing changed (the display's widgets and its
  reduction's ModelFile as before, no new pipeline object).
"""

import json
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
import numpy as np  # noqa: E402
from paraview import servermanager, simple  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

C = T.Checker("test_transfer_function_files")
OUT = os.path.join(T.output_dir(), "transfer_function_files")
if os.path.isdir(OUT):
    shutil.rmtree(OUT)
os.makedirs(OUT)
SAMPLE = 2000


def write_vti(name, channels):
    """channels: [(name, (z, y, x) array)] -> OUT/name, float32 point arrays."""
    return T.write_vti(os.path.join(OUT, name), channels)


def coordinates(proxy):
    array = servermanager.Fetch(proxy).GetPointData().GetArray("ReducedCoordinates")
    return None if array is None else vtk_to_numpy(array).copy()


def widgets_of(display):
    return [float(v) for v in display.GaussianWidgets]


def hidden_of(display):
    return [float(v) for v in display.GaussianWidgetsHidden]


def names_of(display):
    return [str(v) for v in display.GetProperty("GaussianWidgetNames")]


def source_count():
    return len(simple.GetSources())


brain = T.brain_arrays(("ch2", "aal"), step=3).astype(np.float32)
t1, aal = brain[0], brain[1]
nz = t1.shape[0]
plane = t1.shape[1] * t1.shape[2]
fit_path = write_vti("fit.vti", [("ch2", t1), ("aal", aal)])
half = t1.copy()
half[nz // 2:] *= 1.3
half_path = write_vti("half.vti", [("aal", aal), ("ch2", half)])  # other channel order too
t1_only_path = write_vti("only_t1.vti", [("ch2", t1)])

view = simple.CreateView("RenderView")
view.ViewSize = [300, 300]

# --- save: a fitted reduction, its model written beside the file -----------------------
volume = simple.OpenDataFile(fit_path)
_, fitted = mce.reduce_multichannel(volume, "PCA", "6D", ReferenceSampleSize=SAMPLE)
fitted.UpdatePipeline()
fit_coords = coordinates(fitted)
lo, hi = fit_coords.min(axis=0), fit_coords.max(axis=0)
size = float((hi - lo).max())
WIDGETS = []
for i, (q, colour) in enumerate(((0.3, (1, 0, 0)), (0.5, (0, 1, 0)), (0.7, (0, 0, 1)))):
    centre = [float(v) for v in np.quantile(fit_coords, q, axis=0)]
    WIDGETS += centre + [0.07 * size] + list(colour) + [0.0 if i == 2 else 0.8]
HIDDEN = [-1.0, -1.0, 0.65]  # the third widget hidden in the editor, 0.65 remembered
NAMES = ["grey matter", "", "white matter (hidden)"]  # the second widget has no name
display = mce.show_gaussian_tf(fitted, view, widgets=WIDGETS)
display.GaussianWidgetsHidden = HIDDEN
display.GaussianWidgetNames = NAMES
tf_path = os.path.join(OUT, "brain.mcvtf")
saved = mce.save_transfer_function(display, tf_path)
model_path = os.path.join(OUT, "brain.mcvmodel")
with open(tf_path) as f:
    content = json.load(f)
header = mce.read_model(model_path) if os.path.exists(model_path) else None
C.check(saved == tf_path and header is not None,
        "save of a fitted display writes %s and its model brain.mcvmodel beside it" % saved)
C.check(content["format"] == "multichannel-explorer-transfer-function" and
        content["version"] == 1 and content["coordinates"] == "ReducedCoordinates" and
        content["channels"] == ["ch2", "aal"] and
        content["model"] == {"file": "brain.mcvmodel", "crc32": header["crc32"],
                             "method": "PCA", "channels": ["ch2", "aal"]},
        "the file names the format, version, coordinates, channels and the model "
        "(relative path, crc32 %08x, PCA): %s" % (header["crc32"], content["model"]))
C.check([w["hidden"] for w in content["widgets"]] == [False, False, True] and
        content["widgets"][2]["opacity"] == 0.65 and
        [w["sigma"] for w in content["widgets"]] == WIDGETS[3::8] and
        [w["colour"] for w in content["widgets"]] == [WIDGETS[i + 4:i + 7] for i in (0, 8, 16)],
        "the widgets: sigmas, colours exactly, the hidden one with its remembered opacity")
C.check([w.get("name") for w in content["widgets"]] == [NAMES[0], None, NAMES[2]],
        "the widgets' names, none for the widget without one: %s"
        % [w.get("name") for w in content["widgets"]])
C.check(str(fitted.ModelFile) == "" and np.array_equal(coordinates(fitted), fit_coords),
        "saving does not change the fitted reduction (no ModelFile, same coordinates)")

# --- load onto another display: another fit of the same volume -------------------------
volume2 = simple.OpenDataFile(fit_path)
_, other = mce.reduce_multichannel(volume2, "Isomap", "6D", ReferenceSampleSize=SAMPLE)
other.UpdatePipeline()
other_before = coordinates(other)
view2 = simple.CreateView("RenderView")
display2 = mce.show_gaussian_tf(other, view2, widgets=[0.1, 0.1, 0.1, 0.3, 1, 1, 0, 1])
display2.GaussianWidgetNames = ["its own widget"]
loaded = mce.load_transfer_function(display2, tf_path)
C.check(widgets_of(display2) == WIDGETS and hidden_of(display2) == HIDDEN and
        names_of(display2) == NAMES and loaded.names == NAMES,
        "load on another display: GaussianWidgets, GaussianWidgetsHidden and "
        "GaussianWidgetNames identical: %s" % names_of(display2))
other_after = coordinates(other)
C.check(os.path.abspath(str(other.ModelFile)) == model_path and
        other_after is not None and np.array_equal(other_after, fit_coords) and
        not np.array_equal(other_before, fit_coords),
        "load switches the other reduction (Isomap fit) to the model: its ReducedCoordinates "
        "are then the saved display's, bit for bit")

# Saving a display that applies a model names that model and writes no other.
os.makedirs(os.path.join(OUT, "again"))
again = mce.save_transfer_function(display2, os.path.join(OUT, "again", "copy.mcvtf"))
with open(again) as f:
    again_content = json.load(f)
C.check(again_content["model"]["file"] == os.path.join("..", "brain.mcvmodel") and
        again_content["model"]["crc32"] == header["crc32"] and
        not os.path.exists(os.path.join(OUT, "again", "copy.mcvmodel")) and
        again_content["widgets"] == content["widgets"],
        "a display with a ModelFile: the file names that model (%s), no new model written"
        % again_content["model"]["file"])

# A file saved before names were kept (no "name"): loading it clears the display's names,
# which named other widgets.
unnamed = dict(content, widgets=[{k: v for k, v in w.items() if k != "name"}
                                 for w in content["widgets"]])
unnamed_path = os.path.join(OUT, "unnamed.mcvtf")
with open(unnamed_path, "w") as f:
    json.dump(unnamed, f)
mce.load_transfer_function(display2, unnamed_path)
C.check(widgets_of(display2) == WIDGETS and names_of(display2) == [],
        "a file without names: the same widgets, the display's names cleared: %s"
        % names_of(display2))
mce.load_transfer_function(display2, tf_path)

# --- apply to two volumes ----------------------------------------------------------------
before = source_count()
vol_a = simple.OpenDataFile(fit_path)
vol_b = simple.OpenDataFile(half_path)
view_a = simple.CreateView("RenderView")
view_b = simple.CreateView("RenderView")
red_a, disp_a = mce.apply_transfer_function(vol_a, tf_path, view_a)
red_b, disp_b = mce.apply_transfer_function(vol_b, tf_path, view_b)
coords_a, coords_b = coordinates(red_a), coordinates(red_b)
far = (nz // 2) - 3  # slices more than 2 from the change
C.check(disp_a.Representation == "Gaussian TF Volume" and
        widgets_of(disp_a) == WIDGETS and widgets_of(disp_b) == WIDGETS and
        hidden_of(disp_b) == HIDDEN and names_of(disp_b) == NAMES,
        "apply: both volumes shown as Gaussian TF Volume with the file's widgets and names")
C.check(np.array_equal(coords_a, fit_coords) and
        np.array_equal(coords_a[:far * plane], coords_b[:far * plane]),
        "apply: on the fit volume the fit's coordinates; the unchanged slices of the other "
        "volume get identical coordinates (%d voxels), hence identical colours" % (far * plane))
moved = float(np.mean(np.any(coords_a[(nz // 2) * plane:] != coords_b[(nz // 2) * plane:],
                             axis=1)))
C.check(moved > 0.3, "apply: the changed half has other coordinates (%.0f%% of its voxels)"
        % (100 * moved))
red_a.UpdatePropertyInformation()
C.check(red_a.GetProperty("NumberOfOutOfModelVoxels").GetElement(0) == 0,
        "apply: no voxel of the fit volume is outside the model")

# The same camera on both, looking along +y with z up (parallel projection): image rows
# below the change see only unchanged slices, and are the same colour in both pictures.
# Per-voxel classification: the colour of a voxel is a function of its coordinates alone.
pictures = []
for name, v, d in (("a", view_a, disp_a), ("b", view_b, disp_b)):
    d.Classification = "Per voxel"
    d.ShowWidgetLegend = 0  # the volume's colours only (the legend's shares differ)
    v.ViewSize = [300, 300]
    v.OrientationAxesVisibility = 0
    v.UseColorPaletteForBackground = 0
    v.Background = [0.0, 0.0, 0.0]
    simple.Render(v)
    bounds = servermanager.Fetch(vol_a).GetBounds()
    c = [(bounds[2 * i] + bounds[2 * i + 1]) / 2.0 for i in range(3)]
    v.CameraFocalPoint = c
    v.CameraPosition = [c[0], c[1] - 4 * (bounds[3] - bounds[2] + 1), c[2]]
    v.CameraViewUp = [0, 0, 1]
    v.CameraParallelProjection = 1
    v.CameraParallelScale = 0.6 * max(bounds[1] - bounds[0], bounds[5] - bounds[4])
    simple.Render(v)
    png = os.path.join(OUT, "applied_%s.png" % name)
    simple.SaveScreenshot(png, v, ImageResolution=[300, 300])
    image = mce._read_png(png)
    w, h = image.GetDimensions()[:2]
    rgb = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3]
    pictures.append(rgb.astype(int))
ren = view_a.GetRenderer()
ren.SetWorldPoint(c[0], c[1], 3.0 * (far - 2), 1.0)
ren.WorldToDisplay()
row = int(ren.GetDisplayPoint()[1])  # rows 0 .. row-1 (bottom up) show slices < far - 2
low_a, low_b = pictures[0][:row], pictures[1][:row]
lit = int((low_a.max(axis=2) > 20).sum())
C.check(row > 20 and lit > 500 and np.array_equal(low_a, low_b),
        "apply, rendered with one camera: the %d rows below the change are identical "
        "(%d coloured pixels)" % (row, lit))
high_diff = int(np.abs(pictures[0][row + 20:] - pictures[1][row + 20:]).max())
C.check(high_diff > 20, "apply, rendered: the changed half looks different (max difference "
                        "%d)" % high_diff)

# --- state files keep the ModelFile and the widgets --------------------------------------
state = os.path.join(OUT, "tf.pvsm")
simple.SaveState(state)
from paraview import smstate  # noqa: E402

python_state = smstate.get_state()
with open(os.path.join(OUT, "tf_state.py"), "w") as f:
    f.write(python_state)
for kind in ("pvsm", "python"):
    simple.ResetSession()
    mce = T.load_plugin(globals())
    if kind == "pvsm":
        simple.LoadState(state)
    else:
        exec(compile(python_state, "python-state", "exec"), {"__name__": "__state__"})
    reductions = [p for p in simple.GetSources().values()
                  if p.GetXMLName() == "DimensionReduction"]
    with_model = [p for p in reductions if str(p.ModelFile)]
    ok = len(with_model) == 3 and all(os.path.abspath(str(p.ModelFile)) == model_path
                                      for p in with_model)
    same = True
    for p in with_model:
        c = coordinates(p)
        same = same and c is not None and (np.array_equal(c, fit_coords) or
                                           np.array_equal(c[:far * plane], fit_coords[:far * plane]))
    shown = []
    for v in simple.GetViews() if hasattr(simple, "GetViews") else []:
        for rep in v.Representations:
            if rep.GetProperty("GaussianWidgets") is not None and \
                    rep.Representation == "Gaussian TF Volume":
                shown.append((widgets_of(rep), hidden_of(rep)))
    print("     %s state: %s" % (kind, [(w == WIDGETS, h) for w, h in shown]))
    # The displays: the fitted one, the one loaded, the two applied. ParaView's Python
    # state leaves out properties with panel_visibility "never", GaussianWidgetsHidden
    # among them: the hidden widget is there with opacity 0, its remembered opacity not.
    C.check(ok and same and sum(1 for w, h in shown if w == WIDGETS and
                                (h == HIDDEN or kind == "python")) == 4,
            "%s state: 3 reductions with the ModelFile, their coordinates the model's, 4 "
            "displays with the widgets (%d reductions, %d displays)"
            % (kind, len(with_model), len(shown)))
simple.ResetSession()
mce = T.load_plugin(globals())

# --- bad input ---------------------------------------------------------------------------
view = simple.CreateView("RenderView")
volume = simple.OpenDataFile(fit_path)
_, target = mce.reduce_multichannel(volume, "PCA", "6D", ReferenceSampleSize=SAMPLE)
target.UpdatePipeline()
target_display = mce.show_gaussian_tf(target, view, widgets=[0.1, 0.2, 0.3, 0.4, 1, 0, 0, 1])
TARGET_WIDGETS = widgets_of(target_display)

with open(tf_path) as f:
    good = f.read()
bad_dir = os.path.join(OUT, "bad")
os.makedirs(bad_dir)
shutil.copy(model_path, os.path.join(bad_dir, "brain.mcvmodel"))
# Another model under the same name: refitted with another sample.
other_dir = os.path.join(OUT, "refitted")
os.makedirs(other_dir)
_, refit = mce.reduce_multichannel(simple.OpenDataFile(fit_path), "PCA", "6D",
                                   ReferenceSampleSize=SAMPLE, RandomSeed=7)
mce.save_model(refit, os.path.join(other_dir, "brain.mcvmodel"))
simple.Delete(refit)
with open(os.path.join(other_dir, "brain.mcvtf"), "w") as f:
    f.write(good)
nan_text = json.dumps(dict(json.loads(good), widgets=[dict(content["widgets"][0], sigma=0.5)]))
nan_text = nan_text.replace('"sigma": 0.5', '"sigma": NaN')
future = dict(json.loads(good), version=2)
number_name = dict(json.loads(good), widgets=[dict(content["widgets"][0], name=5)])
no_model_dir = os.path.join(OUT, "no_model")
os.makedirs(no_model_dir)
bad = {
    "truncated": (os.path.join(bad_dir, "truncated.mcvtf"), good[:len(good) // 2],
                  "not valid JSON"),
    "not_json": (os.path.join(bad_dir, "not_json.mcvtf"), "P5\n2 2\n255\n", "not valid JSON"),
    "future": (os.path.join(bad_dir, "future.mcvtf"), json.dumps(future), "version 2"),
    "missing_model": (os.path.join(no_model_dir, "brain.mcvtf"), good,
                      "without its model"),
    "checksum": (os.path.join(other_dir, "brain.mcvtf"), None, "another reduction model"),
    "nan": (os.path.join(bad_dir, "nan.mcvtf"), nan_text, "widget 0's sigma is nan"),
    "name": (os.path.join(bad_dir, "name.mcvtf"), json.dumps(number_name),
             "widget 0's name is 5, not text"),
    "missing_file": (os.path.join(bad_dir, "nothing.mcvtf"), None, "cannot be read"),
}
for name, (path, text, words) in bad.items():
    if text is not None:
        with open(path, "w") as f:
            f.write(text)
    count = source_count()
    said = []
    for action in (lambda: mce.load_transfer_function(target_display, path),
                   lambda: mce.apply_transfer_function(volume, path, view)):
        try:
            action()
            said.append(None)
        except ValueError as e:
            said.append(str(e))
    unchanged = (widgets_of(target_display) == TARGET_WIDGETS and str(target.ModelFile) == ""
                 and source_count() == count)
    C.check(all(s is not None and path in s and words in s for s in said) and unchanged,
            "bad file (%s): load and apply raise ValueError naming the file and '%s', nothing "
            "changed: %s" % (name, words, said[0]))

# Saving: another extension, a missing folder, a display that is no Gaussian TF Volume, a
# reduction of an input Features array (no model): ValueError, no file written.
plain_display = simple.Show(volume, view)
feats, from_features = mce.reduce_multichannel(volume, "PCA", "6D", keep_features=True,
                                               ReferenceSampleSize=SAMPLE)
features_display = mce.show_gaussian_tf(from_features, view,
                                        widgets=[0.1, 0.2, 0.3, 0.4, 1, 0, 0, 1])
for name, target, path, words in (
        ("extension", target_display, os.path.join(bad_dir, "widgets.json"), "ends in .mcvtf"),
        ("folder", target_display, os.path.join(bad_dir, "nowhere", "w.mcvtf"),
         "folder does not exist"),
        ("display", plain_display, os.path.join(bad_dir, "plain.mcvtf"), "Gaussian TF Volume"),
        ("features array", features_display, os.path.join(bad_dir, "features.mcvtf"),
         "no model to save")):
    try:
        mce.save_transfer_function(target, path)
        said = None
    except ValueError as e:
        said = str(e)
    C.check(said is not None and words in said and not os.path.exists(path) and
            not os.path.exists(path[:-len(".mcvtf")] + ".mcvmodel"),
            "save (%s): ValueError '%s', nothing written: %s" % (name, words, said))

# A volume without a channel of the model.
t1_only = simple.OpenDataFile(t1_only_path)
count = source_count()
try:
    mce.apply_transfer_function(t1_only, tf_path, view)
    said = None
except ValueError as e:
    said = str(e)
C.check(said is not None and "no channel 'aal'" in said and tf_path in said and
        source_count() == count,
        "apply to a volume without the channel aal: ValueError naming it, no pipeline "
        "object left: %s" % said)
_, t1_reduction = mce.reduce_multichannel(t1_only, "PCA", "6D", ReferenceSampleSize=SAMPLE)
t1_display = mce.show_gaussian_tf(t1_reduction, view, widgets=[0.1, 0.2, 0.3, 0.4, 1, 0, 0, 1])
t1_before = coordinates(t1_reduction)
try:
    mce.load_transfer_function(t1_display, tf_path)
    said = None
except ValueError as e:
    said = str(e)
C.check(said is not None and "no channel 'aal'" in said and
        str(t1_reduction.ModelFile) == "" and
        widgets_of(t1_display) == [0.1, 0.2, 0.3, 0.4, 1, 0, 0, 1] and
        np.array_equal(coordinates(t1_reduction), t1_before),
        "load onto a display of a volume without aal: ValueError naming it; ModelFile, "
        "widgets and coordinates as before: %s" % said)
C.finish()
