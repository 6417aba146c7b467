"""(g) The viewpoint loop and the reduced domain on synthetic volumes with known answers.

* BestViewpoint with OpacitySource = Representation: 5 Gaussian widgets whose centres lie
  on a plane with normal n, in a volume whose coordinates are the voxel positions: the
  best view direction is +-n; and it equals the direction from the same opacity written
  as a channel (a Calculator evaluating 1 - prod(1 - a_i g_i)) through an identity ramp.
* Bad input: widget coordinates missing or 1-component, a widget list whose length is not
  a multiple of 8, sigma <= 0: errors, no crash.
* ReducedDomain: sample size, VoxelId -> the voxel's own coordinates, RGBA equal to the
  formula, same seed same sample, seeded widgets (SeededWidgets) at the clusters.
* When the "Gaussian TF Volume" representation is available: follow_best_viewpoint turns
  the camera to the new plane's normal after the display's widgets change; auto_widgets
  sets the display's widgets; show_dual_domain recolours the domain when they change.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_widget_viewpoint")
out = T.output_dir()
ReducedDomain = simple.ReducedDomain


def plane_widgets(normal, spread=10.0, sigma=2.5, color=(1.0, 0.3, 0.1)):
    """5 widgets on the plane through the origin with this normal: centre and 4 at +-spread
    along two in-plane axes (a cross), so the opacity is flat across n."""
    n = T.unit(normal)
    helper = [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]
    u = T.unit([n[1] * helper[2] - n[2] * helper[1], n[2] * helper[0] - n[0] * helper[2],
                n[0] * helper[1] - n[1] * helper[0]])
    w = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
    centres = [[0.0, 0.0, 0.0]]
    for axis in (u, w):
        for s in (-1.0, 1.0):
            centres.append([s * spread * a for a in axis])
    flat = []
    for c in centres:
        flat += c + [sigma] + list(color) + [1.0]
    return flat


def opacity_expression(widgets):
    """The widgets' opacity as a Calculator expression of coords (independent of the C++)."""
    factors = []
    for i in range(0, len(widgets), 8):
        cx, cy, cz, s, _, _, _, a = widgets[i:i + 8]
        factors.append("(1-%r*exp(-((coordsX-(%r))^2+(coordsY-(%r))^2+(coordsZ-(%r))^2)/%r))"
                       % (a, cx, cy, cz, 2 * s * s))
    return "1-" + "*".join(factors)


wavelet = Wavelet(WholeExtent=[-24, 24, -24, 24, -24, 24])
coords = Calculator(Input=wavelet, Function="coords", ResultArrayName="ReducedCoordinates",
                    ResultArrayType="Float")
normal_a = T.unit([1.0, 2.0, 2.0])
normal_b = T.unit([2.0, -1.0, 0.5])
widgets_a = plane_widgets(normal_a)
widgets_b = plane_widgets(normal_b, color=(0.1, 0.4, 1.0))

# ---- BestViewpoint from the widgets' opacity --------------------------------------------
def best_direction(viewpoint):
    """The BestViewpoint's BestViewDirection after an update."""
    viewpoint.UpdatePipeline()
    viewpoint.UpdatePropertyInformation()
    return [float(x) for x in viewpoint.GetPropertyValue("BestViewDirection")]


bvp = BestViewpoint(Input=coords, OpacitySource="Representation", GaussianWidgets=widgets_a)
best_a = best_direction(bvp)
C.check(T.angle_deg(best_a, normal_a, unsigned=True) < 2.0,
        "widgets on a plane: best direction %s is the plane normal (%.2f deg)"
        % (["%.3f" % x for x in best_a], T.angle_deg(best_a, normal_a, unsigned=True)))

as_channel = Calculator(Input=coords, Function=opacity_expression(widgets_a),
                        ResultArrayName="WidgetOpacity")
ramp = CreatePiecewiseFunction(Points=[0.0, 0.0, 0.5, 0.0, 1.0, 1.0, 0.5, 0.0])
bvp_channel = BestViewpoint(Input=as_channel, Channels=["WidgetOpacity"], OpacityFunction=ramp)
best_channel = best_direction(bvp_channel)
C.check(T.angle_deg(best_a, best_channel, unsigned=True) < 0.5,
        "widget opacity == the same opacity as a channel (%.3f deg)"
        % T.angle_deg(best_a, best_channel, unsigned=True))

bvp.GaussianWidgets = widgets_b
best_b = best_direction(bvp)
C.check(T.angle_deg(best_b, normal_b, unsigned=True) < 2.0,
        "new widgets: best direction follows to the new normal (%.2f deg)"
        % T.angle_deg(best_b, normal_b, unsigned=True))

# ---- NaN coordinates: counted, opacity 0, a warning ----------------------------------------
# Every voxel with x > 20 gets NaN coordinates (4 x 49 x 49 = 9604 voxels, far from the
# widgets): the count is known, the warning names the array, the view stays the normal.
holes = ProgrammableFilter(Input=coords)
holes.Script = """
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
out = self.GetOutput()
out.DeepCopy(self.GetInput())
xyz = vtk_to_numpy(out.GetPointData().GetArray("ReducedCoordinates"))
xyz[xyz[:, 0] > 20, :] = np.nan
out.GetPointData().GetArray("ReducedCoordinates").Modified()
"""
bvp_nan = BestViewpoint(Input=holes, OpacitySource="Representation", GaussianWidgets=widgets_a)
nan_messages = T.Messages(bvp_nan)
bvp_nan.UpdatePipeline()
bvp_nan.UpdatePropertyInformation()
nan_count = int(bvp_nan.GetPropertyValue("NumberOfNonFiniteVoxels"))
best_nan = [float(x) for x in bvp_nan.GetPropertyValue("BestViewDirection")]
C.check(nan_count == 4 * 49 * 49 and nan_messages.any_warning("9604", "ReducedCoordinates"),
        "NaN widget coordinates: %d counted (9604), a warning %s" % (nan_count, nan_messages.warnings))
C.check(T.angle_deg(best_nan, normal_a, unsigned=True) < 2.0,
        "NaN widget coordinates: the view is still the plane normal (%.2f deg)"
        % T.angle_deg(best_nan, normal_a, unsigned=True))
Delete(bvp_nan)
# The ProgrammableFilter's script ran in this namespace and left numpy's max/min/abs/sum
# there: take Python's back for the checks below.
import builtins  # noqa: E402
max, min, abs, sum, all, any = (builtins.max, builtins.min, builtins.abs, builtins.sum,
                                builtins.all, builtins.any)

# ---- Bad input ------------------------------------------------------------------------------
messages = T.Messages(bvp)
for label, props, words in (
        ("length not a multiple of 8", dict(GaussianWidgets=widgets_a[:7]), ("multiple of 8",)),
        ("sigma <= 0", dict(GaussianWidgets=[0, 0, 0, 0.0, 1, 1, 1, 1]), ("sigma",)),
        ("coordinates missing", dict(GaussianWidgets=widgets_a, WidgetCoordinates="nope"),
         ("nope",)),
        ("one-component coordinates", dict(WidgetCoordinates="RTData"), ("2 or 3",))):
    messages.clear()
    for k, v in props.items():
        setattr(bvp, k, v)
    bvp.UpdatePipeline()
    bvp.UpdatePropertyInformation()
    C.check(messages.any_error(*words) and not int(bvp.GetPropertyValue("ViewValid")),
            "BestViewpoint, %s: error (%s)" % (label, (messages.errors or ["none"])[0][:90]))
bvp.WidgetCoordinates = "ReducedCoordinates"
messages.clear()
bvp.GaussianWidgets = [0, 0, 0, 3, 1.5, 0, 0, 2]
bvp.UpdatePipeline()
C.check(messages.any_warning("clamped"), "colour/opacity outside [0,1]: clamped with a warning")

# ---- ReducedDomain --------------------------------------------------------------------------
domain = ReducedDomain(Input=coords, SampleSize=3000, RandomSeed=3, GaussianWidgets=widgets_a)
domain.Coordinates = ["POINTS", "ReducedCoordinates"]
domain.UpdatePipeline()
cloud = servermanager.Fetch(domain)
C.check(cloud.GetNumberOfPoints() == 3000 and cloud.GetNumberOfVerts() == 3000,
        "ReducedDomain: 3000 sampled points, one vertex each (%d)" % cloud.GetNumberOfPoints())
volume = servermanager.Fetch(coords)
voxel_coords = volume.GetPointData().GetArray("ReducedCoordinates")
ids = cloud.GetPointData().GetArray("VoxelId")
rgba = cloud.GetPointData().GetArray("RGBA")
worst_position = worst_colour = 0.0
for i in range(0, 3000, 7):
    voxel = int(ids.GetValue(i))
    p = cloud.GetPoint(i)
    q = voxel_coords.GetTuple3(voxel)
    worst_position = max(worst_position, max(abs(a - b) for a, b in zip(p, q)))
    # The formula, in Python: alpha_i, 1 - prod(1 - alpha_i), alpha-weighted colour.
    alphas, colours = [], []
    for w in range(0, len(widgets_a), 8):
        cx, cy, cz, s, r, g, b, a = widgets_a[w:w + 8]
        d2 = (q[0] - cx) ** 2 + (q[1] - cy) ** 2 + (q[2] - cz) ** 2
        alphas.append(a * math.exp(-d2 / (2 * s * s)))
        colours.append((r, g, b))
    total = sum(alphas)
    expected = [sum(al * c[k] for al, c in zip(alphas, colours)) / total if total > 0 else 0.0
                for k in range(3)]
    expected.append(1.0 - math.prod(1.0 - al for al in alphas))
    got = rgba.GetTuple4(i)
    worst_colour = max(worst_colour, max(abs(g / 255.0 - e) for g, e in zip(got, expected)))
C.check(worst_position < 1e-6, "ReducedDomain: each point sits at its voxel's coordinates")
C.check(worst_colour <= 0.5 / 255 + 1e-6,
        "ReducedDomain: RGBA equals the widget formula (max error %.4f)" % worst_colour)
again = servermanager.Fetch(domain)
C.check([again.GetPointData().GetArray("VoxelId").GetValue(i) for i in range(0, 3000, 97)] ==
        [ids.GetValue(i) for i in range(0, 3000, 97)], "ReducedDomain: same seed, same sample")
widget_points = servermanager.Fetch(domain, None, None, 1)
C.check(widget_points.GetNumberOfPoints() == 5 and
        abs(widget_points.GetPointData().GetArray("Diameter").GetValue(0) - 5.0) < 1e-6,
        "ReducedDomain: the Widgets output has the 5 widgets, diameter 2 sigma")

# Seeding: the volume's coordinates restricted to two blobs -> 2 widgets at the blobs.
blobs = Calculator(Input=coords, ResultArrayName="Blobs", ResultArrayType="Float",
                   Function="(coordsX < 0)*(-10*iHat + 5*jHat) + (coordsX >= 0)*(10*iHat - 5*jHat)"
                            " + 0.02*coords")
seeded = ReducedDomain(Input=blobs, SampleSize=5000, SeedWidgetCount=2, SkipLargestCluster=0)
seeded.Coordinates = ["POINTS", "Blobs"]
seeded.UpdatePipeline()
seeded.UpdatePropertyInformation()
suggestion = [float(v) for v in seeded.GetProperty("SeededWidgets")]
centres = sorted(tuple(round(c) for c in suggestion[i:i + 3]) for i in range(0, len(suggestion), 8))
C.check(len(suggestion) == 16 and centres == [(-10, 5, 0), (10, -5, 0)],
        "SeedWidgetCount=2: widgets at the two blobs %s" % (centres,))

# Settings ReducedDomain cannot honour: errors or warnings, never a silent change.
exact = Calculator(Input=coords, ResultArrayName="Three", ResultArrayType="Float",
                   Function="(coordsX < -8)*iHat + (coordsX > 8)*jHat")  # 3 distinct points
for label, props, kind, words in (
        ("SampleSize 0", dict(SampleSize=0), "error", ("SampleSize", "at least 1")),
        ("SampleSize -1", dict(SampleSize=-1), "error", ("SampleSize", "at least 1")),
        ("SeedWidgetCount 65", dict(SeedWidgetCount=65), "error", ("SeedWidgetCount", "64")),
        ("SeedWidgetOpacity NaN", dict(SeedWidgetCount=2, SeedWidgetOpacity=float("nan")),
         "error", ("SeedWidgetOpacity", "NaN")),
        ("SeedWidgetOpacity 1.5", dict(SeedWidgetCount=2, SeedWidgetOpacity=1.5), "warning",
         ("SeedWidgetOpacity", "outside [0, 1]")),
        ("5 widgets from 3 points", dict(SeedWidgetCount=5, SkipLargestCluster=0), "warning",
         ("5 widgets asked for", "3 seeded", "3 distinct"))):
    odd = ReducedDomain(Input=exact, SampleSize=2000)
    odd.Coordinates = ["POINTS", "Three"]
    odd_messages = T.Messages(odd)
    for name, value in props.items():
        setattr(odd, name, value)
    odd.UpdatePipeline()
    found = (odd_messages.any_error if kind == "error" else odd_messages.any_warning)(*words)
    C.check(found, "ReducedDomain %s: %s mentioning %s (errors %s, warnings %s)"
            % (label, kind, words, odd_messages.errors, odd_messages.warnings))
    Delete(odd)

# ---- With the representation: follow, auto widgets, dual domain -----------------------------
view = CreateView("RenderView")
view.ViewSize = [400, 400]
display = Show(coords, view)
try:
    display.SetRepresentationType(mce.GAUSSIAN_TF_REPRESENTATION)
    has_representation = display.Representation == mce.GAUSSIAN_TF_REPRESENTATION
except Exception as error:  # noqa: BLE001 - the representation is another module
    print("no representation: %s" % error)
    has_representation = False
if C.check(has_representation, "the %r representation is available"
           % mce.GAUSSIAN_TF_REPRESENTATION):
    display.GaussianWidgets = widgets_a
    Render(view)
    follower = mce.follow_best_viewpoint(display, view, frames=4)
    C.check(T.angle_deg(T.camera_direction(view), normal_a, unsigned=True) < 2.0,
            "follow_best_viewpoint: camera along the plane normal (%.2f deg)"
            % T.angle_deg(T.camera_direction(view), normal_a, unsigned=True))
    SaveScreenshot(os.path.join(out, "widget_viewpoint_a.png"), view)
    display.GaussianWidgets = widgets_b  # the observer recomputes and turns the camera
    C.check(T.angle_deg(T.camera_direction(view), normal_b, unsigned=True) < 2.0,
            "after a widget change the camera follows (%.2f deg to the new normal)"
            % T.angle_deg(T.camera_direction(view), normal_b, unsigned=True))
    SaveScreenshot(os.path.join(out, "widget_viewpoint_b.png"), view)
    follower.stop()
    display.GaussianWidgets = widgets_a
    C.check(T.angle_deg(T.camera_direction(view), normal_b, unsigned=True) < 2.0,
            "after stop() the camera stays")

    dual = mce.show_dual_domain(display, view, sample_size=4000)
    C.check(list(dual.filter.GaussianWidgets) == widgets_a, "show_dual_domain: widgets copied")
    display.GaussianWidgets = widgets_b
    C.check(list(dual.filter.GaussianWidgets) == widgets_b,
            "show_dual_domain: the domain follows a widget change")
    SaveScreenshot(os.path.join(out, "widget_dual_domain.png"), dual.domain_view)
    dual.stop()

    widgets = mce.auto_widgets(display, 3)
    C.check(len(widgets) == 24 and list(display.GaussianWidgets) == widgets,
            "auto_widgets: 3 widgets set on the display")
    mce.stop_following()
C.finish()
