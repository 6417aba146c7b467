"""(i) Abort: every filter of the suite stops when AbortExecute is set during its run (the
VTK way: a ProgressEvent observer sets it), on the real brain (Colin27 T1 + AAL + Brodmann).

For MultichannelFeatures, DimensionReduction (Isomap, every voxel placed), BestViewpoint
(HarrisPCA and the viewpoint-entropy baseline):
* an observer sets AbortExecute at the first progress report past 10 %: the filter reports
  nothing more (only the executive's own end-of-run 1.0 follows), gives no error and leaves
  an empty output (no Features / ReducedCoordinates array, no interest points), and it made
  fewer reports than a whole run;
* the same filter, modified and run again without the observer, gives the full result
  (the abort does not stick; as for any VTK filter, an aborted one runs again once
  modified).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_abort")

merged = T.brain_channels()
merged.UpdatePipeline()
t1 = merged.Input[0]  # the Colin27 T1 reader


class AbortAt(object):
    """A ProgressEvent observer that sets AbortExecute at the first report >= `at`, and
    records every report."""

    def __init__(self, algorithm, at):
        self.algorithm = algorithm
        self.at = at
        self.reports = []
        self.aborted_at = None
        self.tag = algorithm.AddObserver("ProgressEvent", self)

    def __call__(self, caller, event):
        progress = caller.GetProgress()
        self.reports.append(progress)
        if self.aborted_at is None and progress >= self.at:
            self.aborted_at = len(self.reports)
            caller.SetAbortExecute(1)

    def remove(self):
        self.algorithm.RemoveObserver(self.tag)


def check_abort(label, proxy, complete):
    """Runs `proxy` once with the abort observer, once without; `complete(output)` says
    whether an output is the full result."""
    algorithm = proxy.GetClientSideObject()
    msgs = T.Messages(proxy)
    observer = AbortAt(algorithm, 0.1)
    proxy.UpdatePipeline()
    observer.remove()
    output = algorithm.GetOutputDataObject(0)
    print("%s: reports %s, aborted at report %s, errors %s" % (
        label, ["%.2f" % p for p in observer.reports], observer.aborted_at, msgs.errors))
    C.check(observer.aborted_at is not None, "%s: progress passed 10 %%" % label)
    # The report that set the flag returns, then the filter stops; the executive ends every
    # run with its own UpdateProgress(1.0).
    tail = observer.reports[observer.aborted_at:] if observer.aborted_at else []
    C.check(tail in ([], [1.0]), "%s: nothing reported after the abort but the executive's "
            "1.0 (%s)" % (label, tail))
    C.check(not msgs.errors, "%s: no error (%s)" % (label, msgs.errors))
    C.check(not complete(output), "%s: the output is left empty" % label)

    msgs.clear()
    counter = AbortAt(algorithm, 2.0)  # never aborts: counts the reports of a whole run
    algorithm.Modified()
    proxy.SMProxy.MarkModified(proxy.SMProxy)
    proxy.UpdatePipeline()
    counter.remove()
    output = algorithm.GetOutputDataObject(0)
    C.check(not msgs.errors, "%s, run again: no error (%s)" % (label, msgs.errors))
    C.check(complete(output), "%s, run again: the full result" % label)
    C.check(len(counter.reports) > len(observer.reports),
            "%s: the aborted run made fewer reports (%d) than a whole run (%d)"
            % (label, len(observer.reports), len(counter.reports)))


def point_array(name, components):
    def complete(output):
        array = output.GetPointData().GetArray(name) if output else None
        return (array is not None and array.GetNumberOfComponents() == components and
                array.GetNumberOfTuples() == merged_points)
    return complete


merged_points = merged.GetDataInformation().GetNumberOfPoints()

features = simple.MultichannelFeatures(Input=merged, FeatureSet="6D")
check_abort("MultichannelFeatures", features, point_array("Features", 6))
features.UpdatePipeline()

reduction = simple.DimensionReduction(Input=features, Method="Isomap",
                                      ReferenceSampleSize=2000, NumberOfLandmarks=200)
check_abort("DimensionReduction", reduction, point_array("ReducedCoordinates", 3))


def has_interest_points(output):
    return output is not None and output.GetNumberOfPoints() > 0


def has_direction(output):
    fd = output.GetFieldData() if output else None
    return fd is not None and fd.GetArray("BestViewDirection") is not None


check_abort("BestViewpoint (HarrisPCA)", simple.BestViewpoint(Input=t1), has_interest_points)
check_abort("BestViewpoint (ViewpointEntropy)",
            simple.BestViewpoint(Input=t1, Method="ViewpointEntropy"), has_direction)

C.finish()
