"""Seeded widgets that let inner structures show, on the real brain.

Chain: Colin27 T1 + AAL + Brodmann (MCV_DATA_DIR) -> MergeChannels -> MultichannelFeatures
(defaults) -> DimensionReduction (defaults) -> "Gaussian TF Volume" -> auto_widgets(4), as
the toolbar's Seed Gaussian Widgets does.

Measured over every voxel of the volume (numpy, the representation's formula):
- a widget's share: the fraction of the head's (Foreground) voxels within its half
  maximum (alpha_i >= a_i / 2);
- a widget's ray opacity: the opacity that widget alone accumulates along the rays
  parallel to the three axes through the head, as the ray caster accumulates it (per
  Scalar Opacity Unit Distance of the display, 1 - prod (1 - alpha)^(step / unit)),
  averaged over the rays that cross the head.
Known answers:
- no drawn widget selects more than half of the head with a ray opacity of 1/2 or more
  (it would hide what is behind it);
- every drawn widget's ray opacity stays below 0.6 (each lets inner structures show);
- the widget of the largest cluster, when it selects more than half of the head's
  voxels (the background-sized class), starts hidden: opacity 0 in GaussianWidgets, its
  opacity remembered in GaussianWidgetsHidden;
- the share SeededWidgetDetails reports for each widget is its cluster's share of the
  sample, and the opacities follow a = (1 - 0.5^(1 / (s L))) / g, capped at 0.5
  (WidgetSeeding.h), recomputed here from the reported s and g.
- Add Widget Here at a voxel in the middle of the head gets an opacity whose ray opacity
  stays below 0.6, and a name;
- show_dual_domain's points and spheres show the widgets' colours with no colour bar.
The same measurement of the former rule (peak 0.5, the largest 0.025; Add Widget Here
0.5) is printed beside.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy as np  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_presentable_seeding")

reduction, view = T.default_brain_reduction((500, 500))
display = mce.show_gaussian_tf(reduction, view)
widgets = [float(v) for v in mce.auto_widgets(display, 4)]
count = len(widgets) // 8
C.check(count == 4, "4 widgets seeded (%d)" % count)

image = reduction.GetClientSideObject().GetOutputDataObject(0)
dims = image.GetDimensions()
coords = mce.coordinate_values(image.GetPointData().GetArray("ReducedCoordinates"))
coords = np.asarray(coords, dtype=np.float64).reshape(-1, 3)
head = vtk_to_numpy(image.GetPointData().GetArray("Foreground")).astype(bool)
unit = float(display.ScalarOpacityUnitDistance)
step = float(image.GetSpacing()[0])
print("volume %s, %d head voxels (%.0f%%), opacity unit distance %.3g"
      % (dims, head.sum(), 100.0 * head.mean(), unit))

drawn = [float(v) for v in display.GaussianWidgets]
hidden = [float(v) for v in display.GetProperty("GaussianWidgetsHidden")]


def weight(w):
    cx, cy, cz, s = widgets[8 * w:8 * w + 4]
    d2 = ((coords - np.array([cx, cy, cz])) ** 2).sum(axis=1)
    return np.exp(-d2 / (2.0 * s * s))


def ray_opacity(alpha):
    """Mean opacity accumulated along axis-parallel rays that cross the head."""
    depth = -np.log1p(-np.clip(alpha, 0.0, 1.0 - 1e-12)) * (step / unit)
    depth = np.where(head, depth, 0.0).reshape(dims[2], dims[1], dims[0])
    inside = head.reshape(dims[2], dims[1], dims[0])
    values = []
    for axis in range(3):
        crosses = inside.any(axis=axis)
        values.append(1.0 - np.exp(-depth.sum(axis=axis)[crosses]))
    return float(np.concatenate(values).mean())


weights = [weight(w) for w in range(count)]
shares = [float((weights[w][head] >= 0.5).mean()) for w in range(count)]
old_rule = [0.025 if w == 0 else 0.5 for w in range(count)]
rows = []
for w in range(count):
    opacity = drawn[8 * w + 7]
    rows.append((w, shares[w], opacity, ray_opacity(opacity * weights[w]),
                 old_rule[w], ray_opacity(old_rule[w] * weights[w])))
    print("widget %d: share of the head %.1f%%, opacity %.4f (ray opacity %.2f); former rule "
          "%.3f (ray opacity %.2f)%s" % (rows[-1][0], 100 * rows[-1][1], rows[-1][2],
                                         rows[-1][3], rows[-1][4], rows[-1][5],
                                         ", hidden" if hidden and hidden[w] >= 0 else ""))

C.check(not any(s > 0.5 and o > 0 and r >= 0.5 for _, s, o, r, _, _ in rows),
        "no drawn widget selects more than half of the head at a ray opacity >= 1/2")
C.check(all(r < 0.6 for _, _, o, r, _, _ in rows if o > 0),
        "every drawn widget lets light through: ray opacities %s"
        % ["%.2f" % r for _, _, o, r, _, _ in rows if o > 0])

# The largest cluster's widget (first): hidden when it is background-sized.
seeding = [p for p in simple.GetSources().values()
           if p.SMProxy.GetXMLName() == "ReducedDomain"]
details = []
for proxy in seeding:
    proxy.UpdatePropertyInformation()
    details = [float(v) for v in proxy.GetProperty("SeededWidgetDetails")]
C.check(len(details) == 3 * count, "SeededWidgetDetails: 3 numbers per widget (%d)"
        % len(details))
big = [w for w in range(count) if details and details[3 * w] > 0.5]
C.check(all(drawn[8 * w + 7] == 0.0 and len(hidden) == count and hidden[w] > 0 for w in big)
        and all(details[3 * w + 1] == (1.0 if w in big else 0.0) for w in range(count)),
        "the widget(s) selecting more than half of the voxels start hidden (%s), their "
        "opacity kept in GaussianWidgetsHidden %s" % (big, hidden))
C.check(big == [0] or not big, "only the largest cluster can be background-sized: %s" % big)

# The rule, recomputed from the reported share and mean weight.
n_cells = (dims[0] - 1) * (dims[1] - 1) * (dims[2] - 1)
b = image.GetBounds()
unit_default = math.sqrt(sum((b[2 * a + 1] - b[2 * a]) ** 2 for a in range(3))) / n_cells ** (1 / 3.)
C.check(abs(unit_default - unit) < 1e-6 * unit,
        "ParaView's default unit distance is the rule's (%.6g, %.6g)" % (unit_default, unit))
ray = (4.0 / 3.0) * (3.0 * head.sum() / (4 * math.pi)) ** (1 / 3.) * step / unit
for w in range(count):
    s, _, g = details[3 * w:3 * w + 3]
    expected = min(0.5, (1 - 0.5 ** (1 / (s * ray))) / g if s * ray > 1 else 0.5 / g)
    actual = drawn[8 * w + 7] if not hidden or hidden[w] < 0 else hidden[w]
    C.check(abs(actual - expected) <= 1e-9 + 1e-6 * expected,
            "widget %d: opacity %.6g = the rule's %.6g (share %.3f, ray %.1f units, mean "
            "weight %.3f)" % (w, actual, expected, s, ray, g))

# Add Widget Here at a voxel in the middle of the head: the opacity presentable_opacity
# gives it lets light through (the former fixed 0.5 is measured beside it).
centre = (dims[0] // 2, dims[1] // 2, dims[2] // 2)
hit = mce.probe(display, centre, mark=False)
domain_messages = T.Messages(seeding[0])
added = mce.add_widget_at(display, hit)
cx, cy, cz, s = added[:4]
gauss = np.exp(-((coords - np.array([cx, cy, cz])) ** 2).sum(axis=1) / (2.0 * s * s))
share = float((gauss[head] >= 0.5).mean())
now, former = ray_opacity(added[7] * gauss), ray_opacity(0.5 * gauss)
names = [str(n) for n in display.GaussianWidgetNames]
print("added widget at %s: share of the head %.1f%%, opacity %.4f (ray opacity %.2f); former "
      "0.5 (ray opacity %.2f)" % (centre, 100 * share, added[7], now, former))
C.check(now < 0.6 and added[7] <= 0.5 and len(names) == count + 1 and names[-1],
        "Add Widget Here lets light through: ray opacity %.2f (former %.2f), named %r"
        % (now, former, names[-1]))
C.check(not domain_messages.warnings and not domain_messages.errors,
        "no message from the domain filter while the display has widgets (%s)"
        % domain_messages.warnings)

# The domain view: coloured by the widgets, no colour bar.
dual = mce.show_dual_domain(display, view)
bars = [rep.SMProxy.IsScalarBarVisible(dual.domain_view.SMProxy)
        for rep in (dual.domain_display, dual.widget_display)]
C.check(not any(bars) and int(dual.domain_display.MapScalars) == 0,
        "the domain view shows the widgets' own colours (MapScalars 0) and no colour bar")
C.finish()
