"""Merge Channels: channels from separate files become one volume only on one grid.

Known answers on the real volumes: Colin27 T1 and the AAL atlas share one grid (181 x 217 x
181, 1 mm), so merging them gives both arrays with the values of AppendAttributes; the T1
and brainsmall.den do not, so the merge is an error naming both inputs and their grids,
with an empty output (AppendAttributes crops one or drops it, in either order). A volume
equal to the T1's in extent but with another spacing is refused too, and the tolerance on
spacing and origin accepts the last-bit differences of separate readers.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

T.load_plugin(globals())
MergeChannels = simple.MergeChannels
C = T.Checker("test_merge_channels")


def merged(inputs):
    proxy = MergeChannels(Input=inputs)
    msgs = T.Messages(proxy)
    proxy.UpdatePipeline()
    print("errors %s" % msgs.errors)
    return proxy, msgs


def with_spacing(source, spacing):
    """`source`'s volume with another spacing (declared in the pipeline information too,
    as a reader would)."""
    f = ProgrammableFilter(Input=source)
    f.OutputDataSetType = "vtkImageData"
    f.CopyArrays = 1
    f.RequestInformationScript = (
        "from vtkmodules.vtkCommonDataModel import vtkDataObject\n"
        "self.GetOutputInformation(0).Set(vtkDataObject.SPACING(), %r, 3)\n" % (spacing,))
    f.Script = "self.GetOutput().SetSpacing(%r)\n" % (spacing,)
    return f


t1 = OpenDataFile(T.data_file("ch2.nii.gz"))
aal = OpenDataFile(T.data_file("aal.nii.gz"))
den = VolPackDenReader(FileName=T.data_file("brainsmall.den"))

# Same grid: both channels, the values AppendAttributes gives.
good, msgs = merged([t1, aal])
append = AppendAttributes(Input=[t1, aal])
append.UpdatePipeline()
C.check(not msgs.errors, "T1 + AAL (one grid): no error")
C.check(sorted(good.PointData.keys()) == sorted(append.PointData.keys()) and
        len(good.PointData.keys()) == 2,
        "T1 + AAL: both channels %s" % good.PointData.keys())
C.check(good.GetDataInformation().GetExtent() == append.GetDataInformation().GetExtent() and
        [good.PointData[k].GetRange() for k in good.PointData.keys()] ==
        [append.PointData[k].GetRange() for k in good.PointData.keys()],
        "T1 + AAL: the extent and value ranges of AppendAttributes")

# Different grids, either order: an error naming both inputs, empty output.
for order, label in (([t1, den], "T1 + brainsmall.den"), ([den, t1], "brainsmall.den + T1")):
    bad, msgs = merged(order)
    C.check(msgs.any_error("not on one grid", "input 2", "input 1", "181 x 217 x 181",
                           "Resample"),
            "%s: error names both inputs, the T1's 181 x 217 x 181 grid and says to resample"
            % label)
    C.check(bad.GetDataInformation().GetNumberOfPoints() == 0, "%s: empty output" % label)
    # The empty output never covers the extent asked of it, so showing and rendering it
    # executes the filter again and again (5 times in all, as the GUI's Apply does): the
    # error is said once...
    Show(bad)
    Render()
    said = lambda: sum("not on one grid" in e for e in msgs.errors)  # noqa: E731
    C.check(said() == 1, "%s: the error said once through Show and Render (said %d times)"
            % (label, said()))
    # ... and again once the inputs change.
    bad.Input = list(reversed(order))
    Render()
    C.check(said() == 2, "%s: said again after the inputs changed (%d in all)" % (label, said()))
    Hide(bad)
    Delete(bad)

# Same extent, another spacing: refused; the same spacing up to rounding: merged.
# (Names are set before the ProgrammableFilter runs: its scripts run in __main__ and
# import numpy's names, spacing among them, over the test's globals.)
for other_spacing, refused in (((1.0, 1.0, 2.0), True), ((1.0 + 1e-9, 1.0, 1.0), False)):
    label = "T1 + AAL with spacing %r" % (other_spacing,)
    result, msgs = merged([t1, with_spacing(aal, other_spacing)])
    if refused:
        C.check(msgs.any_error("not on one grid", "spacing 1 1 2"),
                "%s: error names the other spacing" % label)
        C.check(result.GetDataInformation().GetNumberOfPoints() == 0, "%s: empty output" % label)
    else:
        C.check(not msgs.errors and len(result.PointData.keys()) == 2,
                "%s: merged (a last-bit difference is one grid)" % label)
    Delete(result)

C.finish()
