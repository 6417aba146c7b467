"""The plugin loaded the way the README writes it, LoadPlugin(path, ns=globals()): the
plugin's filters then go into this script's namespace, not into paraview.simple's, and
every helper of the Python package must still find them (reduce_multichannel,
reduced_domain_filter, apply_best_viewpoint), on the real brain (Colin27 T1)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

C = T.Checker("test_load_with_ns")
plugin = os.environ.get("MCV_PLUGIN")
if not plugin:
    print("FAIL: MCV_PLUGIN is not set")
    sys.exit(1)
C.check(not hasattr(simple, "DimensionReduction"), "before: paraview.simple has no plugin filter")
LoadPlugin(plugin, remote=False, ns=globals())
C.check("DimensionReduction" in globals(), "LoadPlugin(..., ns=globals()) filled this namespace")
import multichannel_explorer as mx  # noqa: E402

t1 = OpenDataFile(T.data_file("ch2.nii.gz"))
try:
    feats, red = mx.reduce_multichannel(t1, "PCA", "6D", ReferenceSampleSize=2000)
    red.UpdatePipeline()
    C.check("ReducedCoordinates" in red.PointData.keys(), "reduce_multichannel: coordinates")
    domain = mx.reduced_domain_filter(red, SampleSize=1000)
    domain.UpdatePipeline()
    C.check(domain.GetDataInformation().GetNumberOfPoints() == 1000,
            "reduced_domain_filter: 1000 sampled points")
except RuntimeError as error:
    C.check(False, "the helpers find the filters (%s)" % error)
view = GetActiveViewOrCreate("RenderView")
Show(t1, view).SetRepresentationType("Volume")
result = mx.apply_best_viewpoint(t1, view)
C.check(result.valid, "apply_best_viewpoint: a valid direction %s" % (result.direction,))
C.finish()
