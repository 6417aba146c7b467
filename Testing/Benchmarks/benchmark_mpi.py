"""One run of the main chain under pvbatch (serial or --mpi): the real 3-channel brain
(Colin27 ch2 + AAL + Brodmann, 7.1 M voxels) -> MultichannelFeatures (24D) ->
DimensionReduction (Isomap fitted on 10000, every voxel placed) -> BestViewpoint.
Prints one JSON line of stage times (seconds, wall clock of UpdatePipeline on the first
process, which waits for all). Driven by benchmark_mpi.sh for 1, 2 and 4 processes.
"""
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

T.load_plugin(globals())
from paraview.simple import BestViewpoint, DimensionReduction, MultichannelFeatures  # noqa: E402


def timed(proxy):
    start = time.time()
    proxy.UpdatePipeline()
    return time.time() - start


readers = [simple.OpenDataFile(T.data_file(n))
           for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
merged = simple.AppendAttributes(Input=readers)
feats = MultichannelFeatures(Input=merged, FeatureSet="24D", Device="CPU")
reduction = DimensionReduction(Input=feats, Method="Isomap", Device="CPU")
view = BestViewpoint(Input=merged, Device="CPU")
result = {"processes": servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions(),
          "threads": int(os.environ.get("OMP_NUM_THREADS", "0"))}
result["features"] = timed(feats)  # includes reading the volumes (each process reads them)
result["reduction"] = timed(reduction)
result["viewpoint"] = timed(view)
view.UpdatePropertyInformation()
result["direction"] = [round(float(x), 6) for x in view.GetPropertyValue("BestViewDirection")]
print("MPI-BENCH " + json.dumps(result))
sys.stdout.flush()
