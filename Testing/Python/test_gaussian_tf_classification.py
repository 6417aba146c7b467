"""Per-sample against per-voxel classification of the "Gaussian TF Volume", with known
answers, on synthetic volumes seen along -z with a parallel camera on black:

* a thin band: coordinates (i, 0, 0) at voxel i and one white widget centred half-way
  between voxels 7 and 8 with sigma 0.1: per sample the rays through x = 7.5 meet
  coordinates 7.5 and show a bright band there; per voxel every voxel is 0.5 from the
  centre (alpha ~ exp(-12.5)) and nothing shows;
* piecewise-constant coordinates (two halves with two translucent widgets): both
  classifications give the same picture away from the one boundary, composite and MIP;
* masked voxels (MaskArray, Foreground by default) and NaN coordinates are transparent in
  both;
* opacity per unit length: a uniform slab of depth L under a widget of peak opacity a
  shows the colour times 1 - (1 - a)^(L / u) for the Scalar Opacity Unit Distance u, in
  both classifications (u = 1 and 4);
* a Volume Rendering Mode without the GPU ray caster ("Ray Cast Only"): one error, nothing
  drawn, drawn again with "Smart"; a string array as coordinates: an error;
* Jittering: on by default; on and off draw the same mean brightness, and on changes
  pixels (the sample planes move).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402
import builtins as B  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_gaussian_tf_classification")
MODES = ("Per sample", "Per voxel")


def coordinates(extent, function, name="ReducedCoordinates", array_type="Float"):
    wavelet = simple.Wavelet(WholeExtent=extent)
    calc = simple.Calculator(Input=wavelet, ResultArrayName=name, ResultArrayType=array_type,
                             Function=function)
    calc.UpdatePipeline()
    return calc


def render_both(name, source, view, widgets, bounds, blend="Composite", **props):
    """Screenshots of `source` per sample and per voxel: {mode: Shot}."""
    shots = {}
    display = mce.show_gaussian_tf(source, view, widgets=widgets, blend=blend)
    for name, value in props.items():
        setattr(display, name, value)
    G.look_down_z(view, bounds)
    for mode in MODES:
        display.Classification = mode
        simple.Render(view)
        label = "%s_%s_%s" % (name, mode.replace(" ", "_").lower(), blend.split()[0].lower())
        shots[mode] = G.Shot(view, G.output_path("classification_%s.png" % label))
        C.check(G.info(display)["valid"] == 1, "%s: drawn" % mode)
    simple.Hide(source, view)
    return display, shots


view = G.black_view((480, 240))

# --- the thin band between two voxels --------------------------------------------------
band = coordinates([0, 15, 0, 7, 0, 7], "coordsX*iHat")
display, shots = render_both("band", band, view, [7.5, 0, 0, 0.1, 1, 1, 1, 1], [0, 15, 0, 7, 0, 7])
row = G.project(view, [7.5, 3.5, 3.5])[1]
x_band = G.project(view, [7.5, 3.5, 3.5])[0]
x_voxel = G.project(view, [4.0, 3.5, 3.5])[0]
for mode, s in shots.items():
    print("%s: at x = 7.5 %s, at x = 4 %s" % (mode, s.rgb((x_band, row)), s.rgb((x_voxel, row))))
sample, voxel = shots["Per sample"], shots["Per voxel"]
C.check(B.min(sample.rgb((x_band, row))) >= 150,
        "per sample: a bright band half-way between voxels 7 and 8 %s"
        % sample.rgb((x_band, row)))
C.check(B.max(voxel.rgb((x_band, row))) <= 10,
        "per voxel: nothing there (every voxel is 5 sigma from the centre) %s"
        % voxel.rgb((x_band, row)))
C.check(B.max(sample.rgb((x_voxel, row))) <= 10 and B.max(voxel.rgb((x_voxel, row))) <= 10,
        "both dark far from the widget")
# The band is thin: coordinates within 2.5 sigma of 7.5 lie within 0.25 voxel of x = 7.5.
px_per_voxel = G.project(view, [8.5, 3.5, 3.5])[0] - x_band
lit = [x for x in range(sample.size[0]) if B.max(sample.rgb((x, row))) > 60]
print("band pixels %s (%.1f pixels per voxel)" % (lit and (lit[0], lit[-1]), px_per_voxel))
C.check(lit and lit[-1] - lit[0] + 1 <= 0.6 * px_per_voxel,
        "the band is narrower than 0.6 voxel (%d pixels, a voxel is %.1f)"
        % (lit and lit[-1] - lit[0] + 1, px_per_voxel))

# --- piecewise-constant coordinates: both classifications agree ---------------------
N = 32
halves = coordinates([0, N - 1, 0, N - 1, 0, N - 1],
                     "(0.25 + 0.5 * (coordsX > %d)) * iHat + 0.5 * jHat + 0.5 * kHat" % (N // 2))
WIDGETS = [0.25, 0.5, 0.5, 0.1, 0.9, 0.3, 0.1, 0.15, 0.75, 0.5, 0.5, 0.1, 0.2, 0.4, 1.0, 0.08]


def agree(blend):
    _, shots = render_both("halves", halves, view, WIDGETS, [0, N - 1] * 3, blend=blend)
    sample, voxel = shots["Per sample"], shots["Per voxel"]
    boundary = G.project(view, [N // 2 + 0.5, 0, 0])[0]
    margin = 2 * (G.project(view, [1, 0, 0])[0] - G.project(view, [0, 0, 0])[0])
    worst, total, count = 0, 0, 0
    for y in range(0, sample.size[1], 3):
        for x in range(0, sample.size[0], 3):
            if abs(x - boundary) <= margin:
                continue
            d = B.max(abs(a - b) for a, b in zip(sample.rgb((x, y)), voxel.rgb((x, y))))
            worst, total, count = B.max(worst, d), total + d, count + 1
    left = G.project(view, [N / 4.0, N / 2.0, N / 2.0])
    print("%s: per sample %s per voxel %s at the left half; max difference %d, mean %.2f"
          % (blend, sample.rgb(left), voxel.rgb(left), worst, total / float(count)))
    C.check(B.max(sample.rgb(left)) >= 25, "%s: the translucent widget shows %s"
            % (blend, sample.rgb(left)))
    C.check(worst <= 6 and total / float(count) <= 1.0,
            "%s: per sample equals per voxel on constant coordinates (max %d, mean %.2f)"
            % (blend, worst, total / float(count)))


agree("Composite")
agree("Maximum Intensity")

# --- opacity per unit length ------------------------------------------------------------
slab = coordinates([0, N - 1, 0, N - 1, 0, N - 1], "0.25*iHat + 0.5*jHat + 0.5*kHat")
for u in (1.0, 4.0):
    _, shots = render_both("slab_u%d" % u, slab, view, [0.25, 0.5, 0.5, 0.1, 0.9, 0.3, 0.1, 0.15],
                           [0, N - 1] * 3, ScalarOpacityUnitDistance=u)
    expected = 255 * 0.9 * (1 - (1 - 0.15) ** ((N - 1) / u))
    centre = G.project(view, [N / 2.0, N / 2.0, N / 2.0])
    for mode, s in shots.items():
        red = s.rgb(centre)[0]
        print("unit distance %g, %s: red %d, expected %.1f" % (u, mode, red, expected))
        C.check(abs(red - expected) <= 3, "unit distance %g, %s: red %d = 255 * 0.9 * (1 - "
                "0.85^(31/u)) = %.1f" % (u, mode, red, expected))

# --- masked voxels and NaN coordinates are transparent ----------------------------------
ramp = coordinates([0, N - 1, 0, N - 1, 0, N - 1], "coords/%d" % (N - 1))
masked = simple.Calculator(Input=ramp, ResultArrayName="Foreground",
                           ResultArrayType="Unsigned Char", Function="coordsX < %d" % (N // 2))
nan_right = simple.ProgrammableFilter(Input=ramp)
nan_right.Script = """
out = self.GetOutput()
out.DeepCopy(self.GetInput())
coords = out.GetPointData().GetArray("ReducedCoordinates")
for i in range(out.GetNumberOfPoints()):
    if out.GetPoint(i)[0] >= %d:
        coords.SetComponent(i, 0, float("nan"))
""" % (N // 2)
BIG = [0.5, 0.5, 0.5, 2.0, 1, 1, 1, 1]  # covers every voxel
for label, source in (("mask", masked), ("NaN", nan_right)):
    _, shots = render_both(label, source, view, BIG, [0, N - 1] * 3)
    left = G.project(view, [N / 4.0, N / 2.0, N / 2.0])
    right = G.project(view, [3 * N / 4.0, N / 2.0, N / 2.0])
    for mode, s in shots.items():
        print("%s, %s: left %s right %s" % (label, mode, s.rgb(left), s.rgb(right)))
        C.check(B.min(s.rgb(left)) >= 150 and B.max(s.rgb(right)) <= 10,
                "%s, %s: drawn left, transparent right %s %s"
                % (label, mode, s.rgb(left), s.rgb(right)))

# --- jittering ------------------------------------------------------------------------
sphere = coordinates([0, N - 1, 0, N - 1, 0, N - 1], "coords/%d" % (N - 1))
display = mce.show_gaussian_tf(sphere, view, widgets=[0.5, 0.5, 0.5, 0.25, 1, 0.8, 0.5, 0.05])
view.CameraParallelProjection = 0
simple.ResetCamera(view)
view.CameraPosition = [N * 2.2, N * 1.4, N * 2.9]
simple.Render(view)
means = {}
shots = {}
for jitter in (1, 0):
    display.Jittering = jitter
    simple.Render(view)
    shots[jitter] = G.Shot(view, G.output_path("classification_jitter_%d.png" % jitter))
    s = shots[jitter]
    values = [B.sum(s.rgb((x, y))) for y in range(0, s.size[1], 2) for x in range(0, s.size[0], 2)]
    means[jitter] = B.sum(values) / float(len(values))
changed = B.sum(1 for y in range(0, 240, 2) for x in range(0, 480, 2)
                if shots[0].rgb((x, y)) != shots[1].rgb((x, y)))
print("mean brightness jitter on %.2f off %.2f; %d sampled pixels differ"
      % (means[1], means[0], changed))
C.check(means[0] > 5 and abs(means[1] - means[0]) <= 0.03 * means[0],
        "jittering keeps the mean brightness (%.2f vs %.2f)" % (means[1], means[0]))
C.check(changed > 100, "jittering moves the samples (%d pixels differ)" % changed)
simple.Hide(sphere, view)

# --- a render mode without the GPU ray caster: one clear error, nothing drawn -------------
display = mce.show_gaussian_tf(halves, view, widgets=WIDGETS)
G.look_down_z(view, [0, N - 1] * 3)
msgs = G.messages(display)
for mode in MODES:
    msgs.clear()
    display.Classification = mode
    display.VolumeRenderingMode = "Ray Cast Only"
    simple.Render(view)
    s = G.Shot(view, G.output_path("classification_ray_cast_only.png"))
    print("Ray Cast Only, %s: errors %s, info %s, max pixel %d"
          % (mode, msgs.errors, G.info(display), s.max_channel()))
    C.check(B.sum(1 for e in msgs.errors if "GPU ray caster only" in e and "Smart" in e) == 1
            and G.info(display)["valid"] == 0 and s.max_channel() <= 10,
            "Ray Cast Only, %s: one error naming the mode to use, nothing drawn" % mode)
    display.VolumeRenderingMode = "Smart"
    simple.Render(view)
    s = G.Shot(view, G.output_path("classification_smart_again.png"))
    C.check(G.info(display)["valid"] == 1 and s.max_channel() > 60,
            "back to Smart, %s: drawn again" % mode)
simple.Hide(halves, view)

# --- a coordinate array that is not numeric: a clear error, nothing drawn --------------
names = simple.ProgrammableFilter(Input=halves)
names.Script = """
from vtkmodules.vtkCommonCore import vtkStringArray
out = self.GetOutput()
out.ShallowCopy(self.GetInput())
a = vtkStringArray()
a.SetName("Labels")
a.SetNumberOfTuples(out.GetNumberOfPoints())
out.GetPointData().AddArray(a)
"""
display = mce.show_gaussian_tf(names, view, widgets=WIDGETS, coordinates="Labels")
msgs = G.messages(display)
simple.Render(view)
s = G.Shot(view, G.output_path("classification_string_array.png"))
print("string array: errors %s, info %s, max pixel %d"
      % (msgs.errors, G.info(display), s.max_channel()))
C.check(msgs.any_error("Labels", "not a numeric point array") and G.info(display)["valid"] == 0
        and s.max_channel() <= 10, "a string array as coordinates: an error, nothing drawn")

C.finish()
