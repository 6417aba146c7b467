"""(k) The background mask on a synthetic two-channel volume with known answers.

Two balls in an empty (zero) field: channel A rises from 10 to 130 along x inside a ball at
x = -9, channel B from 25 to 75 along y inside a ball at x = +9; both are 0 elsewhere.

* MultichannelFeatures: Foreground (uint8) is 1 exactly inside the balls (default
  threshold 0), NumberOfBackgroundVoxels counts the rest; BackgroundThreshold 0.5 cuts each
  channel at min + 0.5 (max - min); MaskBackground off: no Foreground array.
* DimensionReduction: draws its sample from the foreground only (NumberOfSampledVoxels),
  places every voxel (finite ReducedCoordinates everywhere) and passes Foreground on.
* ReducedDomain: every sampled VoxelId is foreground; the 2 seeded widgets sit on the two
  balls, more than 2.5 sigma from the background's reduced coordinates,
  in the palette's first two colours; without the mask the cloud is mostly background:
  what the mask prevents.
* BestViewpoint of one all-covering widget: the interest points lie on the balls (the
  background gets opacity 0).
* A volume that is background everywhere: a clear warning, an all-0 mask, and the
  reduction and the domain still run (each warns that the mask marks no voxel).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_background_mask")

SET1 = [(228, 26, 28), (55, 126, 184)]  # ColorBrewer Set1: red, blue


def fetch(proxy):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy)


def values(array):
    return [array.GetValue(i) for i in range(array.GetNumberOfTuples())]


wavelet = Wavelet(WholeExtent=[-20, 20, -14, 14, -12, 12])
ball_a = "((coordsX+9)^2+coordsY^2+coordsZ^2 < 49)"
ball_b = "((coordsX-9)^2+coordsY^2+coordsZ^2 < 36)"
chan_a = Calculator(Input=wavelet, ResultArrayName="A", ResultArrayType="Float",
                    Function="%s*(70+10*(coordsX+9))" % ball_a)
volume = Calculator(Input=chan_a, ResultArrayName="B", ResultArrayType="Float",
                    Function="%s*(50+5*coordsY)" % ball_b)
image = fetch(volume)
a_values = values(image.GetPointData().GetArray("A"))
b_values = values(image.GetPointData().GetArray("B"))
n = len(a_values)
inside = [1 if (a > 0 or b > 0) else 0 for a, b in zip(a_values, b_values)]

# ---- MultichannelFeatures ---------------------------------------------------------------
features = simple.MultichannelFeatures(Input=volume, Channels=["A", "B"])
out = fetch(features)
features.UpdatePropertyInformation()
mask = out.GetPointData().GetArray("Foreground")
if C.check(mask is not None and mask.GetClassName() == "vtkUnsignedCharArray"
           and mask.GetNumberOfComponents() == 1,
           "MaskBackground on by default: a uint8 Foreground array"):
    C.check(values(mask) == inside,
            "Foreground is 1 exactly inside the balls (%d of %d voxels)" % (sum(inside), n))
    C.check(features.GetPropertyValue("NumberOfBackgroundVoxels") == n - sum(inside),
            "NumberOfBackgroundVoxels = %d" % (n - sum(inside)))


def expected_mask(threshold):
    cuts = []
    for vals in (a_values, b_values):
        lo, hi = min(vals), max(vals)
        cuts.append(lo + threshold * (hi - lo))
    return [1 if (a > cuts[0] or b > cuts[1]) else 0 for a, b in zip(a_values, b_values)]


features.BackgroundThreshold = 0.5
half = values(fetch(features).GetPointData().GetArray("Foreground"))
C.check(half == expected_mask(0.5) and 0 < sum(half) < sum(inside),
        "BackgroundThreshold 0.5 cuts each channel at min + 0.5 (max - min) (%d foreground)"
        % sum(half))
features.BackgroundThreshold = 0.0
features.MaskBackground = 0
C.check(fetch(features).GetPointData().GetArray("Foreground") is None,
        "MaskBackground off: no Foreground array")
features.MaskBackground = 1

# ---- DimensionReduction -------------------------------------------------------------------
reduction = simple.DimensionReduction(Input=features, Method="PCA", OutputDimension=3,
                                      ReferenceSampleSize=3000, RandomSeed=1)
reduction.Features = ["POINTS", "Features"]
reduced = fetch(reduction)
reduction.UpdatePropertyInformation()
C.check(reduction.GetPropertyValue("NumberOfSampledVoxels") == sum(inside),
        "the reference sample is drawn from the %d foreground voxels (NumberOfSampledVoxels %s)"
        % (sum(inside), reduction.GetPropertyValue("NumberOfSampledVoxels")))
passed = reduced.GetPointData().GetArray("Foreground")
C.check(passed is not None and values(passed) == inside, "Foreground passed on to the output")
coords = reduced.GetPointData().GetArray("ReducedCoordinates")
C.check(coords.GetNumberOfTuples() == n and
        T.all_finite(coords.GetComponent(i, c) for i in range(n) for c in range(3)),
        "every voxel, background included, has finite ReducedCoordinates")
corner = 0  # voxel (-20, -14, -12): deep background, far from both balls
C.check(inside[corner] == 0, "the corner voxel is background")
background_xyz = [coords.GetComponent(corner, c) for c in range(3)]

log = T.Messages(reduction)
reduction.ReferenceSampleSize = 100000
fetch(reduction)
C.check(log.any_warning("exceeds the number of foreground voxels"),
        "a sample larger than the foreground: all of it, with a warning")
reduction.ReferenceSampleSize = 3000
fetch(reduction)


# ---- ReducedDomain ------------------------------------------------------------------------
def seeded_widgets(source, **props):
    domain = simple.ReducedDomain(Input=source, SampleSize=4000, SeedWidgetCount=2,
                                  RandomSeed=2, **props)
    domain.UpdatePipeline()
    domain.UpdatePropertyInformation()
    flat = [float(v) for v in domain.GetProperty("SeededWidgets")]
    return domain, [flat[i:i + 8] for i in range(0, len(flat), 8)]


def weight_at(widget, xyz):
    d2 = sum((widget[c] - xyz[c]) ** 2 for c in range(3))
    return widget[7] * math.exp(-d2 / (2 * widget[3] ** 2))


domain, widgets = seeded_widgets(reduction)  # SkipLargestCluster stays at its default (on)
cloud = servermanager.Fetch(domain)
ids = cloud.GetPointData().GetArray("VoxelId")
C.check(ids.GetNumberOfTuples() == min(4000, sum(inside)) and
        all(inside[ids.GetValue(i)] for i in range(ids.GetNumberOfTuples())),
        "the domain cloud holds foreground voxels only (%d points)" % ids.GetNumberOfTuples())
C.check(len(widgets) == 2, "2 widgets seeded with the mask (none skipped)")
# The background's reduced coordinates lie outside every widget: more than 2.5 sigma from
# each centre (weight below opacity x exp(-3.1)).
sigmas_away = min([math.sqrt(sum((w[c] - background_xyz[c]) ** 2 for c in range(3))) / w[3]
                   for w in widgets] or [0.0])
C.check(sigmas_away > 2.5, "no seeded centre lies at the background's coordinates (nearest "
        "%.1f sigma away, weight there %.1e)"
        % (sigmas_away, max([weight_at(w, background_xyz) for w in widgets] or [1.0])))
# Each widget on one ball: the widget of the voxels of ball A and of ball B differ.
centre_of = {}
for name, ball in (("A", a_values), ("B", b_values)):
    pts = [i for i in range(n) if ball[i] > 0]
    centre_of[name] = [sum(coords.GetComponent(i, c) for i in pts) / len(pts) for c in range(3)]
nearest = sorted(min(range(len(widgets)),
                     key=lambda k: sum((widgets[k][c] - centre_of[b][c]) ** 2 for c in range(3)))
                 for b in ("A", "B"))
C.check(nearest == [0, 1], "one widget per ball")
C.check([tuple(round(255 * x) for x in w[4:7]) for w in widgets] == SET1,
        "seeded colours are the palette's first two (ColorBrewer Set1 red, blue)")

# Without the mask the background fills the domain cloud: the failure the mask is for.
unmasked_features = simple.MultichannelFeatures(Input=volume, Channels=["A", "B"],
                                                MaskBackground=0)
unmasked = simple.DimensionReduction(Input=unmasked_features, Method="PCA", OutputDimension=3,
                                     ReferenceSampleSize=3000, RandomSeed=1)
unmasked.Features = ["POINTS", "Features"]
plain = fetch(unmasked).GetPointData().GetArray("ReducedCoordinates")
plain_bg = [plain.GetComponent(corner, c) for c in range(3)]
plain_domain, plain_widgets = seeded_widgets(unmasked, SkipLargestCluster=0)
plain_ids = servermanager.Fetch(plain_domain).GetPointData().GetArray("VoxelId")
plain_background = sum(1 for i in range(plain_ids.GetNumberOfTuples())
                       if not inside[plain_ids.GetValue(i)])
C.check(plain_background > plain_ids.GetNumberOfTuples() // 2,
        "without the mask most of the cloud is background (%d of %d points; weight of the "
        "widgets at the background %.2e)" % (plain_background, plain_ids.GetNumberOfTuples(),
                                             max(weight_at(w, plain_bg) for w in plain_widgets)))

# ---- BestViewpoint of the widgets' opacity: the background is transparent ----------------
# One widget covering the whole domain: without the mask its opacity fills the volume (a
# flat box); with it only the two balls are opaque and the interest points lie on them.
everything = [0.0, 0.0, 0.0, 1000.0, 1.0, 1.0, 1.0, 0.8]
ball_centres = [(-9.0, 0.0, 0.0, 7.0), (9.0, 0.0, 0.0, 6.0)]


def farthest_from_balls(viewpoint):
    points = fetch(viewpoint).GetPoints()
    worst = 0.0
    for i in range(points.GetNumberOfPoints()):
        p = points.GetPoint(i)
        worst = max(worst, min(math.sqrt(sum((p[c] - b[c]) ** 2 for c in range(3))) - b[3]
                               for b in ball_centres))
    return worst, points.GetNumberOfPoints()


masked_view = simple.BestViewpoint(Input=reduction, OpacitySource="Representation",
                                   GaussianWidgets=everything, NumberOfInterestPoints=200)
worst, count = farthest_from_balls(masked_view)
C.check(count > 0 and worst < 3.0, "BestViewpoint of the widgets: the %d interest points lie "
        "on the balls (at most %.1f voxels outside), the background is transparent"
        % (count, worst))

# ---- Every voxel background -----------------------------------------------------------------
flat = Calculator(Input=wavelet, ResultArrayName="Flat", ResultArrayType="Float",
                  Function="0*coordsX")
ramp = Calculator(Input=flat, ResultArrayName="Ramp", ResultArrayType="Float",
                  Function="coordsX")
empty = simple.MultichannelFeatures(Input=ramp, Channels=["Flat", "Ramp"],
                                    BackgroundThreshold=1.0)
empty_log = T.Messages(empty)
empty_out = fetch(empty)
empty_mask = empty_out.GetPointData().GetArray("Foreground")
C.check(empty_log.any_warning("every voxel is background", "lower BackgroundThreshold",
                              "turn off MaskBackground"),
        "all background: the warning says what to do")
C.check(empty_mask is not None and max(values(empty_mask)) == 0, "all background: mask all 0")
empty_reduction = simple.DimensionReduction(Input=empty, Method="PCA", OutputDimension=2,
                                            ReferenceSampleSize=500)
empty_reduction.Features = ["POINTS", "Features"]
reduction_log = T.Messages(empty_reduction)
empty_reduced = fetch(empty_reduction)
C.check(empty_reduced.GetPointData().GetArray("ReducedCoordinates") is not None and
        reduction_log.any_warning("marks no voxel"),
        "all background: the reduction samples every voxel, with a warning")
empty_domain = simple.ReducedDomain(Input=empty_reduction, SampleSize=500, SeedWidgetCount=2)
domain_log = T.Messages(empty_domain)
empty_domain.UpdatePipeline()
empty_domain.UpdatePropertyInformation()
C.check(servermanager.Fetch(empty_domain).GetNumberOfPoints() == 500 and
        len(list(empty_domain.GetProperty("SeededWidgets"))) == 16 and
        domain_log.any_warning("marks no voxel"),
        "all background: the domain shows every voxel and seeds widgets, with a warning")
C.finish()
