"""(e) DimensionReduction on the real 3-channel brain (Colin27 ch2 T1 + AAL + Brodmann).

* features -> DimensionReduction (PCA and landmark Isomap): ReducedCoordinates exists with
  finite values for every voxel, the Spectrum table (second output) has rows,
  EigenvalueSpectrum / VarianceRetained / Trustworthiness are readable after
  UpdatePipeline + UpdatePropertyInformation and agree with the field data;
* a screenshot of the reduced domain as a point cloud (a few thousand non-background
  voxels placed at their ReducedCoordinates, coloured by the T1 intensity);
* bad inputs, each an error (or, where the data is still usable, a warning) and no crash:
  not image data, no feature array, a missing array name, one component, an empty
  extent, OutputDimension 4, K >= M, NaN features, M > voxels, a constant feature.

Features come from the MultichannelFeatures filter when the plugin has it; otherwise the
three channels, each scaled to unit range by a Calculator, are the (3D) features.
"""
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import builtins as B  # noqa: E402

from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_reduction")
out = T.output_dir()
if not C.check(hasattr(simple, "DimensionReduction"), "the plugin has DimensionReduction"):
    C.finish()
DimensionReduction = simple.DimensionReduction

merged = T.brain_channels()
merged.UpdatePipeline()
names = merged.PointData.keys()
C.check(len(names) == 3, "three point arrays on one grid: %s" % names)
t1_name, aal_name, ba_name = names[0], names[1], names[2]
voxels = merged.GetDataInformation().GetNumberOfPoints()
print("volume: %d voxels, arrays %s" % (voxels, names))


def make_features(source):
    """(proxy, array name, description): MultichannelFeatures when available."""
    if hasattr(simple, "MultichannelFeatures"):
        feats = simple.MultichannelFeatures(Input=source)
        for prop, value in (("Channels", [t1_name, aal_name, ba_name]),
                            ("FeatureSet", "6D")):
            try:
                setattr(feats, prop, value)
            except Exception as e:  # property names of the features filter
                print("note: MultichannelFeatures.%s not set (%s)" % (prop, e))
        feats.UpdatePipeline()
        if "Features" in feats.PointData.keys():
            arr = feats.PointData["Features"]
            print("MultichannelFeatures components: %s" % [
                arr.GetComponentName(c) for c in range(arr.GetNumberOfComponents())])
            return feats, "Features", "MultichannelFeatures 6D"
        print("note: MultichannelFeatures gave no Features array; using the raw channels")
    # Fallback: the three channels scaled to [0, 1] as a 3-component array.
    terms = []
    for name in (t1_name, aal_name, ba_name):
        lo, hi = source.PointData[name].GetRange(0)
        terms.append("(%s-(%.17g))/%.17g" % (name, lo, (hi - lo) if hi > lo else 1.0))
    calc = Calculator(Input=source)
    calc.ResultArrayName = "Features"
    calc.ResultArrayType = "Float"
    calc.Function = "%s*iHat + %s*jHat + %s*kHat" % tuple(terms)
    calc.UpdatePipeline()
    return calc, "Features", "scaled channels (3D)"


features, feature_name, feature_kind = make_features(merged)
ncomp = features.PointData[feature_name].GetNumberOfComponents()
print("features: %s, %d components" % (feature_kind, ncomp))
C.check(ncomp >= 2, "feature array has %d >= 2 components" % ncomp)


def output_object(proxy, port=0):
    """The filter's output data object (pvbatch: built-in session, same process)."""
    return proxy.GetClientSideObject().GetOutputDataObject(port)


def all_finite_array(array):
    # vtk arrays expose the buffer protocol: no numpy needed.
    mv = memoryview(array).cast("B").cast("f")
    return B.all(map(math.isfinite, mv))


def run_reduction(method, **props):
    label = "%s" % method
    red = DimensionReduction(Input=features, Method=method, **props)
    msgs = T.Messages(red)
    start = time.time()
    red.UpdatePipeline()
    elapsed = time.time() - start
    red.UpdatePropertyInformation()
    print("%s: %.1f s, errors %s warnings %s" % (label, elapsed, msgs.errors, msgs.warnings))
    C.check(not msgs.errors, "%s: no error" % label)
    dim = int(props.get("OutputDimension", 3))
    image = output_object(red, 0)
    coords = image.GetPointData().GetArray("ReducedCoordinates")
    if not C.check(coords is not None, "%s: ReducedCoordinates exists" % label):
        return red, None
    C.check(coords.GetNumberOfTuples() == voxels and coords.GetNumberOfComponents() == dim,
            "%s: ReducedCoordinates has %d tuples x %d components (voxels %d, dim %d)"
            % (label, coords.GetNumberOfTuples(), coords.GetNumberOfComponents(), voxels, dim))
    C.check(coords.GetDataType() == 10, "%s: ReducedCoordinates is float32" % label)
    C.check([coords.GetComponentName(c) for c in range(dim)] ==
            ["dim%d" % (c + 1) for c in range(dim)], "%s: components named dim1..dim%d"
            % (label, dim))
    C.check(all_finite_array(coords), "%s: finite values for every voxel" % label)
    spread = [coords.GetRange(c) for c in range(dim)]
    C.check(B.all(hi > lo for lo, hi in spread), "%s: every coordinate varies %s"
            % (label, spread))
    C.check(image.GetPointData().GetArray(feature_name) is not None and
            image.GetPointData().GetArray(t1_name) is not None,
            "%s: the input arrays are passed through" % label)

    table = output_object(red, 1)
    rows = table.GetNumberOfRows()
    cols = [table.GetColumnName(i) for i in range(table.GetNumberOfColumns())]
    print("%s: Spectrum %d rows, columns %s" % (label, rows, cols))
    C.check(rows > 0 and cols == ["index", "value", "fraction"],
            "%s: Spectrum table has rows and columns index, value, fraction" % label)

    spectrum = [float(x) for x in red.GetPropertyValue("EigenvalueSpectrum")]
    retained = float(red.GetPropertyValue("VarianceRetained"))
    trust = float(red.GetPropertyValue("Trustworthiness"))
    print("%s: spectrum %s, variance retained %.4f, trustworthiness %.4f, device %s, "
          "timings %s" % (label, spectrum, retained, trust, red.GetPropertyValue("DeviceUsed"),
                          [float(x) for x in red.GetPropertyValue("StageTimings")]))
    C.check(len(spectrum) == rows and T.all_finite(spectrum),
            "%s: EigenvalueSpectrum readable (%d values, = table rows)" % (label, len(spectrum)))
    if method == "LLE":  # LLE's eigenvalues are not variances
        C.check(retained == 0.0, "%s: VarianceRetained %.4f is 0 (not a variance method)"
                % (label, retained))
    else:
        C.check(0.0 < retained <= 1.0 + 1e-9, "%s: VarianceRetained %.4f in (0, 1]"
                % (label, retained))
    C.check(0.0 < trust <= 1.0 + 1e-9, "%s: Trustworthiness %.4f in (0, 1]" % (label, trust))
    fd = image.GetFieldData()
    fd_trust = fd.GetArray("Trustworthiness")
    fd_var = fd.GetArray("VarianceRetained")
    C.check(fd_trust is not None and fd_var is not None and
            abs(fd_trust.GetValue(0) - trust) < 1e-12 and abs(fd_var.GetValue(0) - retained) < 1e-12,
            "%s: field data Trustworthiness / VarianceRetained = the properties" % label)
    return red, coords


# Whole brain (7.1 M voxels): a small reference sample keeps the test short.
pca, _ = run_reduction("PCA", ReferenceSampleSize=5000)
pca2, _ = run_reduction("PCA", OutputDimension=2, ReferenceSampleSize=5000)
iso, _ = run_reduction("Isomap", ReferenceSampleSize=2000, NumberOfNeighbors=12,
                       NumberOfLandmarks=200)
# LLE on landmarks (the default) and exact (as many landmarks as reference points).
lle, _ = run_reduction("LLE", ReferenceSampleSize=2000, NumberOfNeighbors=12,
                       NumberOfLandmarks=200)
lle_exact, _ = run_reduction("LLE", ReferenceSampleSize=1000, NumberOfNeighbors=12,
                             NumberOfLandmarks=1000)

# ---- the reduced domain as a point cloud ------------------------------------------------
def point_cloud_shot(red, label, dim=3):
    mask = MaskPoints(Input=red)
    mask.OnRatio = 1
    mask.MaximumNumberofPoints = 12000
    mask.RandomSampling = 1
    mask.RandomSamplingMode = "Randomized Id Strides"
    mask.GenerateVertices = 1
    mask.SingleVertexPerCell = 1
    # Non-background voxels only (T1 above a tenth of its range).
    lo, hi = merged.PointData[t1_name].GetRange(0)
    thr = Threshold(Input=mask)
    thr.Scalars = ["POINTS", t1_name]
    thr.LowerThreshold = lo + 0.1 * (hi - lo)
    thr.UpperThreshold = hi
    place = Calculator(Input=thr)
    place.CoordinateResults = 1
    if dim == 3:
        place.Function = "ReducedCoordinates"
    else:
        place.Function = "ReducedCoordinates_dim1*iHat + ReducedCoordinates_dim2*jHat"
    place.UpdatePipeline()
    n = place.GetDataInformation().GetNumberOfPoints()
    C.check(1000 <= n <= 12000, "%s: point cloud of %d voxels" % (label, n))
    view = T.render_view([600, 500], background=(1, 1, 1), axes=True)
    disp = Show(place, view)
    disp.SetRepresentationType("Points")
    disp.PointSize = 3
    ColorBy(disp, ("POINTS", t1_name))
    disp.RescaleTransferFunctionToDataRange(True, False)
    lut = GetColorTransferFunction(t1_name)
    lut.ApplyPreset("Viridis (matplotlib)", True)
    disp.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    bar.Title = "T1 (%s)" % t1_name
    bar.ComponentTitle = ""
    bar.TitleColor = [0, 0, 0]
    bar.LabelColor = [0, 0, 0]
    title = Text(Text="%s of %s: ReducedCoordinates of %d voxels" % (label, feature_kind, n))
    tdisp = Show(title, view)
    tdisp.Color = [0, 0, 0]
    tdisp.FontSize = 14
    tdisp.WindowLocation = "Upper Center"
    view.ResetCamera()
    if dim == 3:
        view.CameraPosition = [1, -1.5, 1]
        view.CameraFocalPoint = [0, 0, 0]
        view.CameraViewUp = [0, 0, 1]
        view.ResetCamera()
    Render(view)
    shot = os.path.join(out, "reduction_%s.png" % label)
    SaveScreenshot(shot, view)
    # A point cloud covers less of the image than a volume: 2% of the pixels.
    T.image_ok(mce, shot, C, "%s point cloud" % label, min_fraction=0.02)
    return n


# The Python helper: an existing feature array (or a MultichannelFeatures preset).
helper_feats, helper_red = mce.reduce_multichannel(features, "PCA", feature_name, 2,
                                                   ReferenceSampleSize=3000)
helper_red.UpdatePipeline()
helper_coords = output_object(helper_red, 0).GetPointData().GetArray("ReducedCoordinates")
C.check(helper_coords is not None and helper_coords.GetNumberOfComponents() == 2 and
        helper_coords.GetNumberOfTuples() == voxels,
        "reduce_multichannel(features, 'PCA', '%s', 2): 2D ReducedCoordinates" % feature_name)
Delete(helper_red)
if hasattr(simple, "MultichannelFeatures"):
    helper_feats, helper_red = mce.reduce_multichannel(merged, "PCA", "6D", 3,
                                                       ReferenceSampleSize=3000)
    helper_red.UpdatePipeline()
    helper_coords = output_object(helper_red, 0).GetPointData().GetArray("ReducedCoordinates")
    C.check(helper_coords is not None and helper_coords.GetNumberOfComponents() == 3 and
            helper_feats is helper_red,
            "reduce_multichannel(volume, 'PCA', '6D'): one DimensionReduction (fused path)")
    Delete(helper_red)
    helper_feats, helper_red = mce.reduce_multichannel(merged, "PCA", "6D", 3, keep_features=True,
                                                       ReferenceSampleSize=3000)
    helper_red.UpdatePipeline()
    C.check("Features" in helper_red.PointData.keys() and helper_feats is not helper_red,
            "reduce_multichannel(..., keep_features=True): MultichannelFeatures -> reduction")
    Delete(helper_red)
    Delete(helper_feats)

point_cloud_shot(pca, "pca")
point_cloud_shot(pca2, "pca2d", dim=2)
point_cloud_shot(iso, "isomap")
point_cloud_shot(lle, "lle")

# ---- the spectrum (second output) as a bar chart ------------------------------------------
chart = CreateView("XYBarChartView")
chart.ViewSize = [600, 400]
bars = Show(OutputPort(pca, 1), chart)
bars.UseIndexForXAxis = 0
bars.XArrayName = "index"
bars.SeriesVisibility = ["fraction"]
chart.ChartTitle = "PCA spectrum: fraction of the variance per component"
Render(chart)
shot = os.path.join(out, "reduction_spectrum.png")
SaveScreenshot(shot, chart)
T.image_ok(mce, shot, C, "spectrum bar chart", min_fraction=0.02)


# ---- bad inputs: each an error (or a warning) and no crash -------------------------------
def image_source(dims, components, value_expr, name="Features", array_type="vtkFloatArray"):
    """Image data of `dims` with one `components`-component point array whose value for
    voxel (i, j, k), component c, is `value_expr` (Python)."""
    return T.programmable_image(dims, name, value=value_expr, components=components, array_type=array_type)


def bad(label, source, error_words=None, warning_words=None, **props):
    source.UpdatePipeline()  # the Features domain needs the input's arrays
    # The checks of a feature array (the channels' own path is test_fused_reduction's).
    props.setdefault("FeatureSet", "Use input array")
    red = DimensionReduction(Input=source, **props)
    msgs = T.Messages(red)
    red.UpdatePipeline()
    red.UpdatePropertyInformation()
    n = red.GetDataInformation().GetNumberOfPoints()
    print("%s: errors %s warnings %s" % (label, msgs.errors, msgs.warnings))
    if error_words:
        C.check(msgs.any_error(*error_words), "%s: error %s" % (label, error_words))
        C.check(n == 0 and output_object(red, 1).GetNumberOfRows() == 0,
                "%s: nothing written (outputs empty)" % label)
        C.check(len(red.GetPropertyValue("EigenvalueSpectrum")) == 0,
                "%s: no spectrum left over" % label)
    if warning_words:
        C.check(not msgs.errors and msgs.any_warning(*warning_words),
                "%s: warning %s, no error" % (label, warning_words))
        coords = output_object(red, 0).GetPointData().GetArray("ReducedCoordinates")
        C.check(coords is not None and all_finite_array(coords),
                "%s: still a finite result" % label)
    Delete(red)


smooth = "math.sin(0.3 * i + c) + math.cos(0.2 * j * (c + 1)) + 0.1 * k * c"
good = image_source((12, 10, 8), 4, smooth)
bad("not image data", Sphere(), error_words=("not image data",))
noarray = T.image_without_arrays()
bad("no feature array", noarray, error_words=("no point arrays",))
bad("missing array name", good, error_words=("No point array named 'Nope'",),
    Features=["POINTS", "Nope"])
bad("one component", Wavelet(), error_words=("1 component", "nothing to reduce"),
    Features=["POINTS", "RTData"])
empty = T.image_without_arrays(-1)
bad("empty extent", empty, error_words=("empty extent",))
bad("OutputDimension 4", good, error_words=("OutputDimension", "2 or 3"), OutputDimension=4)
bad("OutputDimension 1", good, error_words=("OutputDimension", "2 or 3"), OutputDimension=1)
bad("K >= M", good, error_words=("K",), Method="Isomap", NumberOfNeighbors=50,
    ReferenceSampleSize=40)
nan_src = image_source((12, 10, 8), 4, "(float('nan') if (i, j, k, c) == (3, 4, 5, 1) else %s)"
                       % smooth)
bad("NaN feature", nan_src, error_words=("NaN",))
bad("M > voxels", good, warning_words=("ReferenceSampleSize", "voxels"),
    ReferenceSampleSize=100000)
const_src = image_source((12, 10, 8), 4, "(7.0 if c == 2 else %s)" % smooth)
bad("constant feature", const_src, warning_words=("constant",))
int_src = image_source((12, 10, 8), 4, "int(10 * (%s))" % smooth, array_type="vtkShortArray")
int_src.UpdatePipeline()
red = DimensionReduction(Input=int_src, FeatureSet="Use input array")
msgs = T.Messages(red)
red.UpdatePipeline()
coords = output_object(red, 0).GetPointData().GetArray("ReducedCoordinates")
C.check(not msgs.errors and coords is not None and all_finite_array(coords),
        "int16 features are converted and reduced")

C.finish()
