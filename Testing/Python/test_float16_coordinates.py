"""float16 reduced coordinates (DimensionReduction's CoordinatePrecision) on the
real 3-channel brain (Colin27 T1 + AAL + Brodmann, 7.1 M voxels).

* the fused path (6D Isomap) and the Features-array path (6D PCA), each run with Float32
  and Float16: the Float16 ReducedCoordinates is an unsigned-short array of 3 components
  (half the bytes) whose values are the Float32 ones rounded to binary16, bit for bit
  (numpy's float32 -> float16 rounding), hence within 2^-11 |x| (+ 2^-25 for subnormals);
  its field array ReducedCoordinatesRange holds the decoded minima and maxima;
* the readers: mce.coordinate_values and probe() read both; ReducedDomain samples the same
  voxels at the rounded coordinates; the "Gaussian TF Volume" (per sample and per voxel)
  renders the same picture from both (pixel differences printed; a widget moved by 2 % of
  its sigma, rendered from float32, is the yardstick they must stay well under);
  BestViewpoint on the widgets' opacity finds the same direction.
Screenshots (float16 and float32) go to the test output folder.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402

import numpy  # noqa: E402
from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_float16_coordinates")
VTK_UNSIGNED_SHORT, VTK_FLOAT = 5, 10

t1 = OpenDataFile(T.data_file("ch2.nii.gz"))
aal = OpenDataFile(T.data_file("aal.nii.gz"))
brodmann = OpenDataFile(T.data_file("brodmann.nii.gz"))
merged = AppendAttributes(Input=[t1, aal, brodmann])
merged.UpdatePipeline()
voxels = merged.GetDataInformation().GetNumberOfPoints()
print("brain: %d voxels" % voxels)


def output(proxy):
    return proxy.GetClientSideObject().GetOutputDataObject(0)


def coordinates(proxy):
    return output(proxy).GetPointData().GetArray("ReducedCoordinates")


def reduce_both(label, method, keep_features, **settings):
    """(float32 proxy, float16 proxy) of the same reduction; checks the float16 array."""
    proxies = []
    for precision in ("float32", "float16"):
        _, red = mce.reduce_multichannel(merged, method, "6D", keep_features=keep_features,
                                         coordinate_precision=precision, **settings)
        msgs = T.Messages(red)
        red.UpdatePipeline()
        C.check(not msgs.errors, "%s %s: no errors %s" % (label, precision, msgs.errors))
        proxies.append(red)
    r32, r16 = proxies
    a32, a16 = coordinates(r32), coordinates(r16)
    if not C.check(a32 is not None and a16 is not None, "%s: both have ReducedCoordinates" % label):
        C.finish()
    C.check(a32.GetDataType() == VTK_FLOAT and a16.GetDataType() == VTK_UNSIGNED_SHORT and
            a16.GetNumberOfComponents() == 3 and a16.GetNumberOfTuples() == voxels,
            "%s: Float16 gives an unsigned-short array of 3 components per voxel (%s)"
            % (label, a16.GetClassName()))
    bytes32 = a32.GetNumberOfValues() * a32.GetDataTypeSize()
    bytes16 = a16.GetNumberOfValues() * a16.GetDataTypeSize()
    print("%s: coordinates %d bytes as float32, %d as float16" % (label, bytes32, bytes16))
    C.check(2 * bytes16 == bytes32, "%s: half the bytes (%d of %d)" % (label, bytes16, bytes32))
    x32 = mce.coordinate_values(a32)
    x16 = mce.coordinate_values(a16)
    C.check(x32.dtype == numpy.float32 and x16.dtype == numpy.float32 and x16.shape == (voxels, 3),
            "%s: coordinate_values reads both as float32 (%s, %s)" % (label, x32.shape, x16.shape))
    rounded = x32.astype(numpy.float16)
    C.check((vtk_to_numpy(a16).reshape(-1, 3) == rounded.view(numpy.uint16)).all(),
            "%s: the float16 bits are the float32 coordinates rounded (numpy), bit for bit" % label)
    d = numpy.abs(x16.astype(numpy.float64) - x32)
    bound = numpy.ldexp(numpy.abs(x32.astype(numpy.float64)), -11) + 2.0 ** -25
    span = float((x32.max(axis=0) - x32.min(axis=0)).max())
    print("%s: largest |float16 - float32| %.3g (%.2g of the range %.3g); largest ratio to "
          "2^-11 |x| + 2^-25: %.3f" % (label, d.max(), d.max() / span, span, (d / bound).max()))
    C.check((d <= bound).all(), "%s: |float16 - float32| <= 2^-11 |x| + 2^-25 everywhere" % label)
    bounds = output(r16).GetFieldData().GetArray("ReducedCoordinatesRange")
    C.check(bounds is not None and bounds.GetNumberOfTuples() == 2 and
            all(bounds.GetComponent(0, c) == x16[:, c].min() and
                bounds.GetComponent(1, c) == x16[:, c].max() for c in range(3)),
            "%s: ReducedCoordinatesRange holds the decoded minima and maxima" % label)
    for prop in ("Trustworthiness", "VarianceRetained", "NumberOfSampledVoxels"):
        r16.UpdatePropertyInformation()
        r32.UpdatePropertyInformation()
        C.check(r16.GetPropertyValue(prop) == r32.GetPropertyValue(prop),
                "%s: the same %s" % (label, prop))
    return r32, r16, x32, x16


# The Features-array path (PCA), then the fused path (Isomap), which the readers use.
p32, p16, _, _ = reduce_both("6D PCA, Features array", "PCA", True, ReferenceSampleSize=3000)
Delete(p16)
Delete(p32)

# ---- The memory check counts 6 bytes per voxel (plus a chunk's float scratch) ---------------
# On a float Features array the reduction needs only its coordinates: 7.1 M x 12 bytes =
# 81.4 MiB as float32; as float16 7.1 M x 6 bytes + 1 Mi rows x 12 bytes = 52.7 MiB. A limit
# of 65 MiB refuses the first and lets the second run.
feats = MultichannelFeatures(Input=merged, FeatureSet="6D")
feats.UpdatePipeline()
checks = {}
os.environ["MCV_MEMORY_LIMIT_MB"] = "65"
for precision in ("Float32", "Float16"):
    red = DimensionReduction(Input=feats, FeatureSet="Use input array", Method="PCA",
                             ReferenceSampleSize=2000, CoordinatePrecision=precision)
    red.Features = ["POINTS", "Features"]
    msgs = T.Messages(red)
    red.UpdatePipeline()
    checks[precision] = (list(msgs.errors), coordinates(red) is not None)
    Delete(red)
del os.environ["MCV_MEMORY_LIMIT_MB"]
Delete(feats)
print("65 MiB limit: %s" % checks)
C.check(any("needs 81.4 MiB" in e and "available" in e for e in checks["Float32"][0]) and
        not checks["Float32"][1], "65 MiB: Float32 is refused, 'needs 81.4 MiB ... available'")
C.check(not checks["Float16"][0] and checks["Float16"][1],
        "65 MiB: Float16 (52.7 MiB) runs %s" % checks["Float16"][0])
r32, r16, x32, x16 = reduce_both("6D Isomap, fused", "Isomap", False, ReferenceSampleSize=2000,
                                 NumberOfNeighbors=12, NumberOfLandmarks=200)

# ---- ReducedDomain: the same voxels sampled, at the rounded coordinates -----------------
domains = [ReducedDomain(Input=r, SampleSize=4000, RandomSeed=3) for r in (r32, r16)]
for dom in domains:
    dom.UpdatePipeline()
ids = [vtk_to_numpy(output(dom).GetPointData().GetArray("VoxelId")) for dom in domains]
pts = [vtk_to_numpy(output(dom).GetPoints().GetData()) for dom in domains]
C.check(len(ids[0]) == len(ids[1]) > 1000 and (ids[0] == ids[1]).all(),
        "ReducedDomain samples the same %d voxels from both" % len(ids[0]))
C.check((pts[1] == x16[ids[1].astype(numpy.int64)]).all() and
        (pts[0] == x32[ids[0].astype(numpy.int64)]).all(),
        "ReducedDomain's points are the decoded coordinates of its voxels")
for dom in domains:
    Delete(dom)

# ---- probe(): the voxel's coordinates, decoded ---------------------------------------------
voxel = (90, 108, 90)
hits = [mce.probe(r, voxel, mark=False) for r in (r32, r16)]
pid = hits[0].point_id
C.check(list(hits[1].coordinates) == [float(v) for v in x16[pid]] and
        list(hits[0].coordinates) == [float(v) for v in x32[pid]],
        "probe() reads the coordinates of both (float16: %s, float32: %s)"
        % (hits[1].coordinates, hits[0].coordinates))

# ---- The Gaussian TF Volume renders the same picture from both ----------------------------
view = G.black_view((500, 420))
disp32 = mce.show_gaussian_tf(r32, view)
widgets = list(mce.auto_widgets(disp32, 4, seed=0))
# Every widget at peak 0.5 (auto_widgets makes large ones faint and may hide one): the
# yardstick below, a 2 %-of-sigma move, then changes the picture visibly.
for w in range(len(widgets) // 8):
    widgets[8 * w + 7] = 0.5
disp32.GaussianWidgets = widgets
Hide(r32, view)
disp16 = mce.show_gaussian_tf(r16, view, widgets=widgets)
Hide(r16, view)
for d in (disp32, disp16):  # the volumes' colours only (the legend's shares may differ)
    d.ShowWidgetLegend = 0
simple.Render(view)
view.CameraPosition = [300.0, -420.0, 260.0]
view.CameraFocalPoint = [90.0, 108.0, 90.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
view.CameraViewAngle = 30.0


def shot(display, source, name):
    """The volume of `display` alone, as pixels (numpy, rows x cols x 3)."""
    for other in (r32, r16):
        Hide(other, view)
    Show(source, view)
    simple.Render(view)
    s = G.Shot(view, G.output_path(name))
    rgb = vtk_to_numpy(s.scalars)[:, :3].astype(numpy.int32)
    return rgb


def render_pair(classification):
    disp32.Classification = classification
    disp16.Classification = classification
    disp32.GaussianWidgets = widgets
    disp16.GaussianWidgets = widgets
    tag = classification.replace(" ", "_").lower()
    a = shot(disp32, r32, "float16_%s_float32.png" % tag)
    b = shot(disp16, r16, "float16_%s_float16.png" % tag)
    # The yardstick: float32 with the first drawn widget (auto_widgets may start one
    # hidden, at opacity 0) moved by 2 % of its sigma along x.
    first = next(w for w in range(len(widgets) // 8) if widgets[8 * w + 7] > 0)
    moved = list(widgets)
    moved[8 * first] += 0.02 * widgets[8 * first + 3]
    disp32.GaussianWidgets = moved
    c = shot(disp32, r32, "float16_%s_moved.png" % tag)
    disp32.GaussianWidgets = widgets
    lit = float((a.max(axis=1) > 20).mean())
    diff, yard = numpy.abs(a - b), numpy.abs(a - c)
    print("%s: %.0f%% of the pixels lit; float16 vs float32: max %d, mean %.4f, 99.9th "
          "percentile %.1f; widget moved by 2%% of sigma: max %d, mean %.4f"
          % (classification, 100 * lit, diff.max(), diff.mean(), numpy.percentile(diff, 99.9),
             yard.max(), yard.mean()))
    C.check(lit > 0.05, "%s: the brain is drawn (%.0f%% of the pixels lit)" % (classification, 100 * lit))
    C.check(diff.mean() < 0.25 * yard.mean() and numpy.percentile(diff, 99.9) <= 8,
            "%s: float16 and float32 render the same picture (mean pixel difference %.4f, "
            "under a quarter of a 2%%-of-sigma widget move's %.4f)"
            % (classification, diff.mean(), yard.mean()))


render_pair("Per sample")
render_pair("Per voxel")
disp16.Classification = "Per sample"
disp32.Classification = "Per sample"

# ---- Picking through the volume and a widget sized by the coordinates' range ---------------
for other in (r32, r16):
    Hide(other, view)
Show(r16, view)
simple.Render(view)
hit = mce.probe_at_pixel(view, 250, 210, display=disp16, mark=False)
Hide(r16, view)
Show(r32, view)
hit32 = mce.probe_at_pixel(view, 250, 210, display=disp32, mark=False)
Hide(r32, view)
Show(r16, view)
C.check(hit is not None and list(hit.coordinates) == [float(v) for v in x16[hit.point_id]],
        "probe_at_pixel through the float16 volume picks a voxel and reads its coordinates (%s)"
        % str(None if hit is None else (hit.index, hit.coordinates)))
# Both are sampled by interpolation (float16 decoded per voxel first): the same spot.
apart = math.sqrt(sum((a - b) ** 2 for a, b in zip(hit.index, hit32.index))) if hit and hit32 else -1
print("picked voxel: float16 %s, float32 %s, %.2f voxels apart"
      % (str(hit and hit.index), str(hit32 and hit32.index), apart))
C.check(0 <= apart <= 3, "probe_at_pixel picks the same spot from both (%.2f voxels apart)" % apart)
span = float((x16.max(axis=0) - x16.min(axis=0)).max())
added = mce.add_widget_at(disp16, [0.0, 0.0, 0.0])
C.check(abs(added[3] - 0.05 * span) <= 1e-6 * span,
        "add_widget_at sizes sigma from the decoded range (%.5f = 5%% of %.4f)" % (added[3], span))
disp16.GaussianWidgets = widgets

# ---- BestViewpoint on the widgets' opacity: the same direction -----------------------------
directions = []
for source in (r32, r16):
    for other in (r32, r16):
        Hide(other, view)
    Show(source, view)
    result = mce.apply_best_viewpoint(source, view)
    C.check(result.valid, "best viewpoint of the widgets found (%s)"
            % ("float16" if source is r16 else "float32"))
    directions.append(result.direction)
angle = T.angle_deg(directions[0], directions[1], unsigned=True)
print("best viewpoint: float32 %s, float16 %s, %.3f degrees apart"
      % ([round(v, 4) for v in directions[0]], [round(v, 4) for v in directions[1]], angle))
C.check(angle < 1.0, "BestViewpoint finds the same direction from both (%.3f degrees apart)" % angle)

C.finish()
