"""The "Gaussian TF Volume" representation on the real 3-channel brain.

Colin27 ch2 (T1) + AAL + Brodmann -> MultichannelFeatures (6D) -> DimensionReduction
(landmark Isomap, 3D, a small reference sample for speed) -> two widgets, red and green,
at the densest spots of the low and high first-coordinate thirds of the tissue voxels that
map farthest from the background (a spot of the reduced domain).
Checks: the voxels nearest each centre get that widget's colour (the formula, evaluated
here), and the rendered images (maximum intensity and composite) show both colours:
enough clearly red and clearly green pixels; empty space skipping leaves the pictures as
they are; the baked table (PerSampleEvaluation "Baked table") draws the exact
evaluation's picture within 6/255 (composite, the oblique view) for these 2 widgets at
peak opacity 0.5 (auto_widgets' cap), 8 and 64 seeded by auto_widgets, and the 2 at a
quarter of their sigma (where a widget is too narrow for the table, the exact
evaluation); at peak opacity 1 the table's picture is printed against the exact one (its
interpolation error shows there: the reason the table is not the default). Screenshots
go to the test output folder.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402
import builtins as B  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_gaussian_tf_brain")

t1 = simple.OpenDataFile(T.data_file("ch2.nii.gz"))
aal = simple.OpenDataFile(T.data_file("aal.nii.gz"))
brodmann = simple.OpenDataFile(T.data_file("brodmann.nii.gz"))
merged = simple.AppendAttributes(Input=[t1, aal, brodmann])
merged.UpdatePipeline()
names = merged.PointData.keys()
C.check(len(names) == 3, "three channels on one grid: %s" % names)

feats, reduction = mce.reduce_multichannel(
    merged, "Isomap", "6D", output_dimension=3, ReferenceSampleSize=2000,
    NumberOfNeighbors=12, NumberOfLandmarks=200)
try:
    feats.Channels = list(names)
except AttributeError:
    pass
reduction.UpdatePipeline()
image = reduction.GetClientSideObject().GetOutputDataObject(0)
coords = image.GetPointData().GetArray("ReducedCoordinates")
t1_values = image.GetPointData().GetArray(names[0])
if not C.check(coords is not None and coords.GetNumberOfComponents() == 3,
               "ReducedCoordinates (3D) from Isomap"):
    C.finish()

# Widgets away from the background: everything outside the head maps to one spot of the
# reduced domain, so the centres are taken among tissue voxels far from that spot.
lo, hi = t1_values.GetRange(0)
n = coords.GetNumberOfTuples()


def median_point(ids):
    return [sorted(coords.GetComponent(i, c) for i in ids)[len(ids) // 2] for c in range(3)]


def dist(a, b):
    return math.sqrt(B.sum((x - y) ** 2 for x, y in zip(a, b)))


background = median_point([i for i in range(0, n, 97)
                           if t1_values.GetTuple1(i) < lo + 0.05 * (hi - lo)])
brain = [i for i in range(0, n, 53) if t1_values.GetTuple1(i) > lo + 0.3 * (hi - lo)]
C.check(len(brain) > 1000, "%d brain voxels sampled" % len(brain))
far = B.sorted(brain, key=lambda i: dist(coords.GetTuple3(i), background))
far = far[len(far) // 2:]  # the half of the tissue farthest from the background
far.sort(key=lambda i: coords.GetComponent(i, 0))
k = len(far) * 3 // 10
span = dist(coords.GetTuple3(far[0]), coords.GetTuple3(far[-1]))


def densest(group):
    """The group voxel with the most group voxels within 5% of the span: a cluster centre."""
    members = [coords.GetTuple3(i) for i in group[::B.max(1, len(group) // 1500)]]
    candidates = members[::B.max(1, len(members) // 200)]
    radius = 0.05 * span
    return list(B.max(candidates, key=lambda c: B.sum(1 for m in members
                                                       if dist(c, m) < radius)))


centres = [densest(far[:k]), densest(far[-k:])]
sigma = 0.15 * B.min(dist(centres[0], background), dist(centres[1], background),
                     dist(centres[0], centres[1]))
sample = brain
widgets = centres[0] + [sigma, 1, 0, 0, 1] + centres[1] + [sigma, 0, 1, 0, 1]
print("background %s, centres %s, sigma %.4g" % (background, centres, sigma))


def expected_rgba(x):
    """The documented formula, evaluated here (reference for the core's output)."""
    alphas, colours = [], []
    for w in range(len(widgets) // 8):
        c = widgets[8 * w:8 * w + 3]
        s = widgets[8 * w + 3]
        d2 = B.sum((a - b) ** 2 for a, b in zip(x, c))
        alphas.append(widgets[8 * w + 7] * math.exp(-d2 / (2 * s * s)))
        colours.append(widgets[8 * w + 4:8 * w + 7])
    total = B.sum(alphas)
    opacity = 1 - math.prod(1 - a for a in alphas)
    rgb = [B.sum(a * c[k] for a, c in zip(alphas, colours)) / total if total > 0 else 0
           for k in range(3)]
    return rgb + [opacity]


for label, centre, channel in (("red", centres[0], 0), ("green", centres[1], 1)):
    near = B.sorted(sample, key=lambda i: B.sum(
        (a - b) ** 2 for a, b in zip(coords.GetTuple3(i), centre)))[:20]
    rgbas = [expected_rgba(coords.GetTuple3(i)) for i in near]
    C.check(B.all(r[channel] > 0.9 and r[3] > 0.5 for r in rgbas),
            "the 20 sampled voxels nearest the %s centre are %s and opaque (min %.2f)"
            % (label, label, B.min(r[channel] for r in rgbas)))

view = G.black_view((500, 500))
display = mce.show_gaussian_tf(reduction, view, widgets=widgets, blend="Maximum Intensity")
msgs = G.messages(display)
view.CameraPosition = [0, -1, 0]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 0, 1]
view.ResetCamera()
simple.Render(view)
state = G.info(display)
print("info %s, errors %s" % (state, msgs.errors))
C.check(state["valid"] == 1 and not msgs.errors, "rendered without error")


def colour_pixels(shot):
    red = green = 0
    w, h = shot.size
    for y in range(0, h, 2):
        for x in range(0, w, 2):
            r, g, b = shot.rgb((x, y))
            if r >= 60 and r > 2 * B.max(g, b):
                red += 1
            elif g >= 60 and g > 2 * B.max(r, b):
                green += 1
    return red, green


for blend, name in (("Maximum Intensity", "gaussian_tf_brain_mip.png"),
                    ("Composite", "gaussian_tf_brain_composite.png")):
    display.GaussianBlendMode = blend
    simple.Render(view)
    shot = G.Shot(view, G.output_path(name))
    red, green = colour_pixels(shot)
    print("%s: %d red, %d green pixels (of %d sampled) -> %s"
          % (blend, red, green, shot.size[0] * shot.size[1] // 4, shot.path))
    C.check(red >= 200 and green >= 200,
            "%s: both widget colours appear (%d red, %d green pixels)" % (blend, red, green))

# Empty space skipping leaves the picture as it is without it: both blends, the front
# view and an oblique one (rays across brick faces at every angle).
C.check(display.EmptySpaceSkipping == "Automatic", "EmptySpaceSkipping is Automatic by default")
default_bricks = G.info(display)
visible_widgets = sum(1 for i in range(len(display.GaussianWidgets) // 8)
                      if display.GaussianWidgets[8 * i + 7] > 0)
C.check(default_bricks["bricks"][0] > 0 and default_bricks["skipping_used"] ==
        (default_bricks["bricks"][2] <= 0.6 * visible_widgets),
        "Automatic: the bricks exactly when a reached brick lists at most 60 %% of the widgets "
        "(%s)" % (default_bricks,))
for blend, turn, stem in (("Composite", False, "gaussian_tf_brain_composite"),
                          ("Maximum Intensity", False, "gaussian_tf_brain_mip"),
                          ("Composite", True, "gaussian_tf_brain_oblique")):
    display.GaussianBlendMode = blend
    if turn:
        camera = view.GetActiveCamera()
        camera.Azimuth(37)
        camera.Elevation(23)
    state = G.skipping_unchanged(C, view, display, "%s%s" % (blend, ", oblique" if turn else ""),
                                 stem, maximum_intensity=blend == "Maximum Intensity")
    bricks, empty, listed = state["bricks"]
    C.check(bricks > 0 and empty > bricks // 10 and 0 < listed <= 2,
            "%s: a widget table with empty bricks (%d of %d bricks empty, %.2f widgets per "
            "reached brick)" % (blend, empty, bricks, listed))

# The baked table against the exact evaluation: composite, the oblique view.
display.GaussianBlendMode = "Composite"
display.EmptySpaceSkipping = 0


def table_against_exact(label, stem, values, tolerance=True):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    display.GaussianWidgets = values
    shots = {}
    for evaluation in ("Exact", "Baked table"):
        display.PerSampleEvaluation = evaluation
        simple.Render(view)
        shots[evaluation] = G.Shot(view, G.output_path("%s_%s.png" % (
            stem, evaluation.split()[-1].lower())))
    display.UpdatePropertyInformation()
    how = str(display.GetPropertyValue("GaussianTFEvaluationUsed"))
    x, y = (vtk_to_numpy(shots[e].scalars)[:, :3].astype(np.int32) for e in ("Exact", "Baked table"))
    d = np.abs(x - y).max(axis=1)
    largest, share = int(d.max()), float((d > 2).mean())
    print("%s: %s; table vs exact: largest %d/255, %.3f %% of pixels > 2/255, brightest %d"
          % (label, how, largest, 100 * share, shots["Exact"].max_channel()))
    C.check(shots["Exact"].max_channel() > 30, "%s: something is drawn" % label)
    if tolerance:
        C.check(largest <= 6 and share <= 0.005,
                "%s: the table's picture is the exact one within 6/255 (largest %d/255, %.3f %% "
                "of pixels > 2/255)" % (label, largest, 100 * share))
    return how


half = list(widgets)
half[7] = half[15] = 0.5
how = table_against_exact("2 widgets, peak opacity 0.5", "gaussian_tf_brain_table_two", half)
C.check(how.startswith("table "), "2 widgets: through the table (%s)" % how)
table_against_exact("2 widgets, peak opacity 1 (not checked)", "gaussian_tf_brain_table_opaque",
                    widgets, tolerance=False)
for count in (8, 64):
    seeded = [float(v) for v in mce.auto_widgets(reduction, count, seed=0)]
    table_against_exact("%d seeded widgets" % count, "gaussian_tf_brain_table_%d" % count, seeded)
narrow = list(widgets)
narrow[3] /= 4.0
narrow[11] /= 4.0
table_against_exact("2 widgets at sigma / 4", "gaussian_tf_brain_table_narrow", narrow)
display.PerSampleEvaluation = "Exact"

C.finish()
