"""DimensionReduction Method=UMAP on the real 3-channel brain (Colin27 ch2 T1 + AAL +
Brodmann), 24D MultichannelFeatures.

* UMAP and landmark Isomap (its defaults: K = 50, L = 500) on the same reference sample
  (same ReferenceSampleSize and RandomSeed): UMAP's reported trustworthiness is at least
  Isomap's (the issue's point: 0.94 against 0.85 at 24D);
* every voxel of the 7.1 M gets finite ReducedCoordinates (the out-of-sample step);
* the spectrum is UMAP's (the Laplacian eigenvalues of its spectral start, fraction 0) or
  empty after a random start, which a warning then explains;
* MinimumDistance outside [0, 1] is an error (determinism: TestUMAP.cpp).
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
C = T.Checker("test_umap")

merged = T.brain_channels()
features = simple.MultichannelFeatures(Input=merged)
features.Channels = merged.PointData.keys()
features.FeatureSet = "24D"
features.UpdatePipeline()
voxels = features.GetDataInformation().GetNumberOfPoints()
C.check(features.PointData["Features"].GetNumberOfComponents() == 24, "24 features per voxel")

SAMPLE = dict(ReferenceSampleSize=3000, RandomSeed=3)


def run(method, **props):
    red = simple.DimensionReduction(Input=features, Method=method, **SAMPLE, **props)
    msgs = T.Messages(red)
    start = time.time()
    red.UpdatePipeline()
    red.UpdatePropertyInformation()
    trust = float(red.GetPropertyValue("Trustworthiness"))
    print("%s: %.1f s (fit, place, total ms %s), trustworthiness %.4f, errors %s, warnings %s"
          % (method, time.time() - start, [float(x) for x in red.GetPropertyValue("StageTimings")],
             trust, msgs.errors, msgs.warnings))
    C.check(not msgs.errors, "%s: no error" % method)
    return red, msgs, trust


def coordinates(red):
    return red.GetClientSideObject().GetOutputDataObject(0).GetPointData().GetArray("ReducedCoordinates")


iso, _, trust_iso = run("Isomap")
umap, umap_msgs, trust_umap = run("UMAP", NumberOfNeighbors=15)
C.check(trust_umap >= trust_iso, "UMAP's trustworthiness %.4f >= Isomap's %.4f on the same sample"
        % (trust_umap, trust_iso))

coords = coordinates(umap)
C.check(coords is not None and coords.GetNumberOfTuples() == voxels and coords.GetNumberOfComponents() == 3,
        "ReducedCoordinates: 3 components for each of the %d voxels" % voxels)
values = memoryview(coords).cast("B").cast("f")  # vtk arrays expose the buffer protocol
C.check(B.all(map(math.isfinite, values)), "every voxel has finite UMAP coordinates")
C.check(B.all(coords.GetRange(c)[1] > coords.GetRange(c)[0] for c in range(3)), "every coordinate varies")

spectrum = [float(x) for x in umap.GetPropertyValue("EigenvalueSpectrum")]
table = umap.GetClientSideObject().GetOutputDataObject(1)
fractions = table.GetColumnByName("fraction")
if umap_msgs.any_warning("connected components"):
    C.check(spectrum == [], "random start (graph in pieces): no spectrum")
else:
    C.check(len(spectrum) == 3 and B.all(0.0 < v < 2.0 for v in spectrum) and spectrum == sorted(spectrum),
            "spectral start: 3 normalised-Laplacian eigenvalues in (0, 2), ascending: %s" % spectrum)
    C.check(B.all(fractions.GetValue(i) == 0.0 for i in range(table.GetNumberOfRows())),
            "the Spectrum table's fraction column is 0 (not variances)")
C.check(umap.GetClientSideObject().GetOutputDataObject(0).GetFieldData()
        .GetAbstractArray("ReductionMethod").GetValue(0) == "UMAP", "field data ReductionMethod = UMAP")

# Bad MinimumDistance: an error naming it, no output.
umap.MinimumDistance = 1.5
umap_msgs.clear()
umap.UpdatePipeline()
C.check(umap_msgs.any_error("MinimumDistance"), "MinimumDistance 1.5: an error naming it %s" % umap_msgs.errors)
C.check(coordinates(umap) is None, "MinimumDistance 1.5: no ReducedCoordinates")

C.finish()
