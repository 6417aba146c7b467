"""The fused path: DimensionReduction on the channels of the real 3-channel
brain (Colin27 T1 + AAL + Brodmann, 7.1 M voxels) against MultichannelFeatures ->
DimensionReduction with the same settings.

* 24D + Isomap (the main job's settings) and 6D + PCA: every voxel's ReducedCoordinates
  within 1e-5 of the coordinate range of the chain's (printed: the largest difference),
  the same Foreground mask, the same spectrum, trustworthiness and sampled voxel count;
  the fused output has no Features array;
* FeatureSet Automatic (the default) on the chain's output reduces its Features array; on
  the channels it takes the fused path (24D);
* progress: at least one report per slab of the placement; an abort between slabs leaves
  an empty output, and the filter runs again afterwards;
* a volume whose coordinates cannot fit gets "needs ... available" before any work.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_fused_reduction")

merged = T.brain_channels()
merged.UpdatePipeline()
channels = list(merged.PointData.keys())
voxels = merged.GetDataInformation().GetNumberOfPoints()
print("brain: %d voxels, channels %s" % (voxels, channels))


def output(proxy):
    return proxy.GetClientSideObject().GetOutputDataObject(0)


def array(proxy, name):
    a = output(proxy).GetPointData().GetArray(name)
    return None if a is None else vtk_to_numpy(a)


def compare(label, feature_set, method, **settings):
    feats = MultichannelFeatures(Input=merged, FeatureSet=feature_set)
    chain = DimensionReduction(Input=feats, Method=method, FeatureSet="Use input array",
                               **settings)
    chain.Features = ["POINTS", "Features"]
    chain.UpdatePipeline()
    chain.UpdatePropertyInformation()
    fused = DimensionReduction(Input=merged, Method=method, FeatureSet=feature_set, **settings)
    msgs = T.Messages(fused)
    fused.UpdatePipeline()
    fused.UpdatePropertyInformation()
    C.check(not msgs.errors, "%s: fused run without errors %s" % (label, msgs.errors))
    expected, got = array(chain, "ReducedCoordinates"), array(fused, "ReducedCoordinates")
    if not C.check(got is not None and expected is not None and got.shape == expected.shape,
                   "%s: ReducedCoordinates for every voxel" % label):
        return
    span = float((expected.max(axis=0) - expected.min(axis=0)).max())
    worst = float(abs(got.astype("float64") - expected).max())
    print("%s: largest difference %.3g of a coordinate range %.3g (%.2g of it)"
          % (label, worst, span, worst / span))
    C.check(worst <= 1e-5 * span, "%s: coordinates within 1e-5 of the range of the chain's" % label)
    C.check((array(fused, "Foreground") == array(chain, "Foreground")).all(),
            "%s: the same Foreground mask" % label)
    C.check(array(fused, "Features") is None, "%s: no Features array in the fused output" % label)
    for prop in ("NumberOfSampledVoxels", "NumberOfFeaturesUsed"):
        C.check(fused.GetPropertyValue(prop) == chain.GetPropertyValue(prop),
                "%s: the same %s (%s)" % (label, prop, fused.GetPropertyValue(prop)))
    for prop in ("Trustworthiness", "VarianceRetained"):
        a, b = float(fused.GetPropertyValue(prop)), float(chain.GetPropertyValue(prop))
        C.check(abs(a - b) <= 1e-6, "%s: the same %s (%.6f, %.6f)" % (label, prop, a, b))
    Delete(fused)
    Delete(chain)
    Delete(feats)


compare("24D Isomap", "24D", "Isomap", NumberOfNeighbors=10, NumberOfLandmarks=500,
        ReferenceSampleSize=10000)
compare("6D PCA", "6D", "PCA", ReferenceSampleSize=5000)

# Automatic: the Features array when there is one, else the channels' 24D set.
feats = MultichannelFeatures(Input=merged, FeatureSet="6D")
auto_chain = DimensionReduction(Input=feats, Method="PCA", ReferenceSampleSize=2000)
auto_chain.UpdatePipeline()
auto_chain.UpdatePropertyInformation()
C.check(auto_chain.GetPropertyValue("NumberOfFeaturesUsed") == 6,
        "Automatic on MultichannelFeatures' output reduces its 6D Features array")
auto_fused = DimensionReduction(Input=merged, Method="PCA", ReferenceSampleSize=2000)
auto_fused.UpdatePipeline()
auto_fused.UpdatePropertyInformation()
C.check(auto_fused.GetPropertyValue("NumberOfFeaturesUsed") == 24 and
        array(auto_fused, "Features") is None,
        "Automatic on the channels computes the 24D set itself (%s features used)"
        % auto_fused.GetPropertyValue("NumberOfFeaturesUsed"))
Delete(auto_chain)
Delete(feats)

# Progress per slab, and an abort between slabs.
algorithm = auto_fused.GetClientSideObject()
reports = []


def record(caller, event):
    reports.append(caller.GetProgress())


tag = algorithm.AddObserver("ProgressEvent", record)
auto_fused.Method = "Isomap"
auto_fused.NumberOfNeighbors = 10
auto_fused.NumberOfLandmarks = 200
auto_fused.UpdatePipeline()
algorithm.RemoveObserver(tag)
placement = [p for p in reports if 0.6 <= p <= 0.95]
C.check(len(placement) >= 3, "progress reported through the placement (%d reports in it)"
        % len(placement))


class AbortAt(object):
    def __init__(self, at):
        self.at = at
        self.done = False

    def __call__(self, caller, event):
        if not self.done and caller.GetProgress() >= self.at:
            self.done = True
            caller.SetAbortExecute(1)


tag = algorithm.AddObserver("ProgressEvent", AbortAt(0.7))
msgs = T.Messages(auto_fused)
auto_fused.RandomSeed = 1
auto_fused.UpdatePipeline()
algorithm.RemoveObserver(tag)
C.check(not msgs.errors and output(auto_fused).GetNumberOfPoints() == 0,
        "an abort during the placement leaves an empty output, no error")
auto_fused.RandomSeed = 2
auto_fused.UpdatePipeline()
C.check(array(auto_fused, "ReducedCoordinates") is not None,
        "after an abort the filter runs again to the end")
Delete(auto_fused)

# Memory: the fused estimate, before any work.
os.environ["MCV_MEMORY_LIMIT_MB"] = "10"
small = DimensionReduction(Input=merged, FeatureSet="24D")
msgs = T.Messages(small)
small.UpdatePipeline()
del os.environ["MCV_MEMORY_LIMIT_MB"]
print("10 MiB: %s" % msgs.errors)
C.check(msgs.any_error("needs", "available", "slab"),
        "too little memory: 'needs ... available' with the fused estimate")
Delete(small)

C.finish()
