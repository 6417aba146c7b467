"""(b) Bad inputs: each gives a clear error or warning, never a crash or NaN.

The filter's own messages are caught with vtkCommand Error/Warning observers on its
server-side object (pvbatch runs a built-in session, so that object is in-process).
Cases: not image data, no point array, a missing array name, an empty extent, a single
slice (2D: its normal is the answer), NaN/Inf voxels, one extreme voxel (3e38) that alone
decides the view, NumberOfInterestPoints <= 0, a
constant volume, and broken .den files for the reader.
"""
import math
import os
import struct
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import builtins as B  # noqa: E402  (ProgrammableSource scripts may shadow all/abs/... in __main__)

from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_bad_inputs")


def run(label, source, **props):
    """Runs BestViewpoint on `source`; returns (filter, messages, results)."""
    bvp = BestViewpoint(Input=source, **props)
    msgs = T.Messages(bvp)
    bvp.UpdatePipeline()
    bvp.UpdatePropertyInformation()
    res = {k: [float(x) for x in bvp.GetPropertyValue(k)]
           for k in ("BestViewDirection", "WorstViewDirection", "ViewUp", "EigenvalueSpectrum")}
    res["ViewValid"] = int(bvp.GetPropertyValue("ViewValid"))
    res["points"] = bvp.GetDataInformation().GetNumberOfPoints()
    print("%s: errors %s warnings %s" % (label, msgs.errors, msgs.warnings))
    C.check(B.all(T.all_finite(res[k]) for k in ("BestViewDirection", "WorstViewDirection",
                                               "ViewUp", "EigenvalueSpectrum")),
            "%s: no NaN/Inf in the results" % label)
    return bvp, msgs, res


def image_source(dims, script_body, array_type="vtkFloatArray", name="values"):
    """Image data of `dims` whose values come from `script_body` (Python computing `v`
    from i, j, k)."""
    return T.programmable_image(dims, name, body=script_body, array_type=array_type, scalars=True)


# ---- not image data ------------------------------------------------------------------
sphere = Sphere()
bvp, msgs, res = run("polydata input", sphere)
C.check(msgs.any_error("not image data"), "polydata input: error 'not image data'")
C.check(res["points"] == 0 and res["ViewValid"] == 0, "polydata input: empty output")
Delete(bvp)

# ---- no point array -----------------------------------------------------------------
empty_arrays = T.image_without_arrays()
bvp, msgs, res = run("no point array", empty_arrays)
C.check(msgs.any_error("no point scalar array"), "no point array: error 'no point scalar array'")
C.check(res["points"] == 0, "no point array: empty output")
Delete(bvp)

# ---- missing array name ---------------------------------------------------------------
wavelet = Wavelet(WholeExtent=[-10, 10, -10, 10, -10, 10])
# An opacity function with one node: ParaView draws it as that opacity everywhere, so the
# opacity volume is constant and there is no view (read as a step it found corners).
one_node = CreatePiecewiseFunction(Points=[150.0, 0.5, 0.5, 0.0])
bvp, msgs, res = run("one-node opacity function", wavelet, OpacityFunction=one_node)
C.check(res["ViewValid"] == 0 and msgs.any_warning("is constant"),
        "one-node opacity function: constant opacity, as ParaView draws it (no view, a warning)")
Delete(bvp)

bvp, msgs, res = run("missing array", wavelet, Channels=["NoSuchArray"])
C.check(msgs.any_error("NoSuchArray", "RTData"),
        "missing array: error names the array and the available ones")
Delete(bvp)

# ---- empty extent ---------------------------------------------------------------------
empty = T.image_without_arrays(-1)
bvp, msgs, res = run("empty extent", empty)
C.check(msgs.any_error("empty extent"), "empty extent: error 'empty extent'")
Delete(bvp)

# ---- NumberOfInterestPoints <= 0 ----------------------------------------------------------
for n in (0, -5):
    bvp, msgs, res = run("N=%d" % n, wavelet, NumberOfInterestPoints=n)
    C.check(msgs.any_error("NumberOfInterestPoints", "positive"),
            "N=%d: error 'NumberOfInterestPoints must be positive'" % n)
    C.check(res["points"] == 0, "N=%d: empty output" % n)
    Delete(bvp)

# ---- a 2D image: a single slice; its normal is the answer ---------------------------------
slice2d = Wavelet(WholeExtent=[-20, 20, -20, 20, 0, 0])
bvp, msgs, res = run("single slice", slice2d)
C.check(not msgs.errors, "single slice: no error")
C.check(res["ViewValid"] == 1 and B.abs(B.abs(res["BestViewDirection"][2]) - 1) < 1e-6,
        "single slice: best direction is the slice normal %s" % res["BestViewDirection"])
C.check(res["points"] > 0, "single slice: %d interest points" % res["points"])
Delete(bvp)

# ---- NaN/Inf voxels: opacity 0, a warning with their count ------------------------------
# Bright blobs on the plane z = 12 (so the answer is known: view along z), plus NaN and
# Inf voxels away from them.
blobs = image_source((24, 24, 24), """
v = 0.0
for (cx, cy) in ((6, 6), (6, 17), (17, 6), (17, 17), (12, 12)):
    v += math.exp(-((i - cx) ** 2 + (j - cy) ** 2 + (k - 12) ** 2) / 3.0)
if (i, j) == (2, 2) and k in (3, 20):
    v = float('nan')
if (i, j, k) == (21, 2, 4):
    v = float('inf')
""")
bvp, msgs, res = run("NaN/Inf voxels", blobs)
C.check(not msgs.errors, "NaN/Inf voxels: no error")
C.check(msgs.any_warning("3 voxel(s) hold NaN/Inf"), "NaN/Inf voxels: warning gives the count (3)")
C.check(int(bvp.GetPropertyValue("NumberOfNonFiniteVoxels")) == 3, "NaN/Inf voxels: NumberOfNonFiniteVoxels = 3")
C.check(res["ViewValid"] == 1 and B.abs(B.abs(res["BestViewDirection"][2]) - 1) < 1e-3,
        "NaN/Inf voxels: view along the blob plane's normal %s" % res["BestViewDirection"])
Delete(bvp)

# ---- one extreme voxel: 3e38 in a [0, 1] volume stretches the default ramp so that only it
# is visible and it alone decides the view: a warning says so and what to do. Without it, the
# same blobs give no such warning.
blob_field = """
v = 0.0
for (cx, cy) in ((6, 6), (6, 17), (17, 6), (17, 17), (12, 12)):
    v += math.exp(-((i - cx) ** 2 + (j - cy) ** 2 + (k - 12) ** 2) / 3.0)
"""
for label, extra, warned in (("one 3e38 voxel", "if (i, j, k) == (3, 20, 5):\n    v = 3e38\n", True),
                             ("no extreme voxel", "", False)):
    bvp, msgs, res = run(label, image_source((24, 24, 24), blob_field + extra))
    C.check(not msgs.errors and msgs.any_warning("Only 1 of", "alone decide the view",
                                                  "OpacityFunction") == warned,
            "%s: %s" % (label, "a warning says it alone decides the view and to set an "
                        "OpacityFunction" if warned else "no few-visible-voxels warning"))
    Delete(bvp)

# ---- constant volume: warning, no direction, no NaN ----------------------------------------
const = image_source((16, 16, 16), "v = 7.0")
bvp, msgs, res = run("constant volume", const)
C.check(not msgs.errors, "constant volume: no error")
C.check(len(msgs.warnings) > 0, "constant volume: a warning")
C.check(res["ViewValid"] == 0 and res["BestViewDirection"] == [0.0, 0.0, 0.0],
        "constant volume: ViewValid 0, no direction")
view = CreateView("RenderView")
Show(const, view)
Render(view)
before = [float(x) for x in view.CameraPosition]
result = mce.apply_best_viewpoint(const, view)
C.check(not result.valid and [float(x) for x in view.CameraPosition] == before,
        "constant volume: apply_best_viewpoint leaves the camera and says valid=False")
Delete(bvp)

# ---- Channels: a non-numeric array is refused ----------------------------------------------
# (Wavelet + a string field would need numpy; the message path is shared with 'missing'.)

# ---- broken .den files ------------------------------------------------------------------------
tmp = tempfile.mkdtemp(prefix="mcv_den_")
not_den = os.path.join(tmp, "not_a_volume.den")
with open(not_den, "wb") as f:
    f.write(b"P6\n# this is a PPM image, not a density file\n" + bytes(100))
truncated = os.path.join(tmp, "truncated.den")
header = struct.pack("<h27hhi", 1, *([0, 0, 0, 3, 3, 3, 4, 4, 4] * 3), 0, 64)
with open(truncated, "wb") as f:
    f.write(header + bytes(10))  # 10 of 64 voxels
inconsistent = os.path.join(tmp, "inconsistent.den")
with open(inconsistent, "wb") as f:
    f.write(struct.pack("<h27hhi", 1, *([0, 0, 0, 3, 3, 3, 4, 4, 4] * 3), 0, 65) + bytes(65))
swapped = os.path.join(tmp, "bigendian.den")
with open(swapped, "wb") as f:
    f.write(struct.pack(">h27hhi", 1, *([0, 0, 0, 3, 3, 3, 4, 4, 4] * 3), 0, 64) +
            bytes(range(64)))
for path, words in ((not_den, "not a VolPack"), (truncated, "truncated"),
                    (inconsistent, "inconsistent header"),
                    (os.path.join(tmp, "missing.den"), "cannot open")):
    reader = VolPackDenReader(FileName=path)
    msgs = T.Messages(reader)
    reader.UpdatePipeline()
    print("%s: errors %s" % (os.path.basename(path), msgs.errors))
    C.check(msgs.any_error(words), "%s: error '%s'" % (os.path.basename(path), words))
    C.check(reader.GetDataInformation().GetNumberOfPoints() == 0,
            "%s: no output" % os.path.basename(path))
    Delete(reader)
# A consistent header over more data than it describes: read as the header says, with a
# warning naming the trailing bytes.
trailing = os.path.join(tmp, "trailing.den")
with open(trailing, "wb") as f:
    f.write(header + bytes(range(64)) + bytes(1 << 20))
reader = VolPackDenReader()
msgs = T.Messages(reader)
reader.FileName = trailing
reader.UpdatePipeline()
print("trailing.den: warnings %s" % msgs.warnings)
C.check(not msgs.errors and msgs.any_warning("1048576 bytes after", "not read") and
        reader.GetDataInformation().GetNumberOfPoints() == 64,
        "trailing.den: the 64 voxels read, a warning about the 1048576 bytes after them")
Delete(reader)
reader = VolPackDenReader(FileName=swapped)
msgs = T.Messages(reader)
reader.UpdatePipeline()
rng = reader.PointData["Density"].GetRange() if reader.PointData["Density"] else None
C.check(not msgs.errors and tuple(reader.GetDataInformation().GetExtent()) == (0, 3, 0, 3, 0, 3)
        and rng == (0.0, 63.0), "big-endian .den: read (4x4x4, values 0..63)")

# A volume too large for this process's memory (MCV_MEMORY_LIMIT_MB stands in for a small
# machine): each filter stops with a message saying how much it needs and how much there is.
big = Wavelet(WholeExtent=[-40, 40, -40, 40, -40, 40])  # 81^3 = 531441 voxels
big_features = MultichannelFeatures(Input=big)
big_features.UpdatePipeline()  # fits: the limit is set below, for the filters under test
os.environ["MCV_MEMORY_LIMIT_MB"] = "1"
for label, proxy in (("BestViewpoint", BestViewpoint(Input=big)),
                     ("MultichannelFeatures", MultichannelFeatures(Input=big)),
                     ("DimensionReduction", DimensionReduction(Input=big_features))):
    msgs = T.Messages(proxy)
    proxy.UpdatePipeline()
    print("%s with 1 MiB: errors %s" % (label, msgs.errors))
    C.check(msgs.any_error("needs", "MiB", "available", "MPI ranks"),
            "%s: too large for memory -> how much is needed and how much is available" % label)
del os.environ["MCV_MEMORY_LIMIT_MB"]

C.finish()
