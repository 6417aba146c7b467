"""PrintSelf of the suite's filters (what print() of the VTK object shows): every member it
names on its own line "Name: value", at the object's indent, with its current value; a
fixed-size array as its values separated by spaces. Known answers: the values set here and
the documented defaults."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_print_self")


def printed(proxy):
    """The lines of PrintSelf of the proxy's VTK object, without their indent."""
    proxy.UpdateVTKObjects()
    return [line.strip() for line in str(proxy.GetClientSideObject()).splitlines()]


def check_lines(name, lines, expected):
    """Each expected line once, in this order."""
    at = [lines.index(e) if lines.count(e) == 1 else -1 for e in expected]
    C.check(-1 not in at and at == sorted(at),
            "%s prints %s in order (missing or repeated: %s)"
            % (name, expected, [e for e, i in zip(expected, at) if i < 0]))


image = T.programmable_image((4, 4, 4), "a")

features = simple.MultichannelFeatures(Input=image)
features.Normalization = "MinMax"
features.BackgroundThreshold = 0.25
check_lines("MultichannelFeatures", printed(features),
            ["Intensity: 1", "Gradient: 0", "GradientMagnitude: 1", "Laplacian: 0",
             "LocalMean: 0", "LocalVariance: 0", "Normalization: 1", "MaskBackground: 1",
             "BackgroundThreshold: 0.25", "NumberOfFeatures: 0",
             "NumberOfBackgroundVoxels: 0"])

domain = simple.ReducedDomain(Input=image)
domain.SampleSize = 1234
domain.RandomSeed = 7
check_lines("ReducedDomain", printed(domain),
            ["SampleSize: 1234", "RandomSeed: 7", "SeedWidgetCount: 0",
             "SeedWidgetOpacity: 0.5", "SkipLargestCluster: 1"])

viewpoint = simple.BestViewpoint(Input=image)
viewpoint.HarrisK = 0.01
check_lines("BestViewpoint", printed(viewpoint),
            ["NumberOfInterestPoints: 2048", "GaussianSigma: 1.5", "KernelWidth: 5",
             "HarrisK: 0.01", "Method: 0", "EntropySamples: 400", "EntropyImageSize: 128",
             "BestViewDirection: 0 0 0", "ViewValid: 0"])
C.finish()
