"""(d) Multichannel input: Colin27 ch2 (T1) with the AAL and Brodmann atlases on the same
grid, a real 3-channel volume.

* three arrays (AppendAttributes) and one 3-component array (Calculator) give the same
  view: every component of every array is a channel;
* the order of the channels does not matter (maximum over channels);
* a channel that is zero everywhere changes nothing (and is reported as constant);
* the multichannel result is valid, the camera follows it, the screenshot is not blank;
* the Channels lists leave out ParaView's bookkeeping arrays (after ResampleToImage).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import builtins as B  # noqa: E402

from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_multichannel")
out = T.output_dir()

merged = T.brain_channels()
merged.UpdatePipeline()
names = merged.PointData.keys()
print("arrays:", names)
C.check(len(names) == 3, "three point arrays on one grid: %s" % names)
t1_name, aal_name, ba_name = names[0], names[1], names[2]


def directions(source, channels, **props):
    bvp = BestViewpoint(Input=source, Channels=channels, **props)
    msgs = T.Messages(bvp)
    bvp.UpdatePipeline()
    bvp.UpdatePropertyInformation()
    res = {k: [float(x) for x in bvp.GetPropertyValue(k)]
           for k in ("BestViewDirection", "WorstViewDirection", "EigenvalueSpectrum")}
    res["valid"] = int(bvp.GetPropertyValue("ViewValid"))
    res["points"] = bvp.GetDataInformation().GetNumberOfPoints()
    res["warnings"] = list(msgs.warnings)
    res["errors"] = list(msgs.errors)
    Delete(bvp)
    return res


three = directions(merged, [t1_name, aal_name, ba_name])
print("3 arrays:", three)
C.check(three["valid"] == 1 and three["points"] == 2048 and not three["errors"],
        "3 channels: valid, 2048 interest points")

# One 3-component array holding the same three channels.
vec = Calculator(Input=merged)
vec.ResultArrayName = "T1_AAL_BA"
vec.Function = "%s*iHat + %s*jHat + %s*kHat" % (t1_name, aal_name, ba_name)
vec.UpdatePipeline()
C.check(vec.PointData["T1_AAL_BA"].GetNumberOfComponents() == 3, "3-component array built")
comps = directions(vec, ["T1_AAL_BA"])
angle = T.angle_deg(comps["BestViewDirection"], three["BestViewDirection"])
C.check(comps["valid"] == 1 and angle < 1e-6,
        "one 3-component array == three arrays (%.2g deg)" % angle)

# Order of the channels.
order = directions(merged, [ba_name, t1_name, aal_name])
angle = T.angle_deg(order["BestViewDirection"], three["BestViewDirection"])
C.check(angle < 1e-6, "channel order does not matter (%.2g deg)" % angle)

# A zero channel changes nothing (maximum over channels), with a warning.
zero = Calculator(Input=merged)
zero.ResultArrayName = "Zero"
zero.Function = "0*%s" % t1_name
single = directions(zero, [t1_name])
with_zero = directions(zero, [t1_name, "Zero"])
angle = T.angle_deg(with_zero["BestViewDirection"], single["BestViewDirection"])
C.check(angle < 1e-6, "a zero channel changes nothing (%.2g deg)" % angle)
C.check(B.any("constant" in w for w in with_zero["warnings"]),
        "a zero channel is reported as constant")
print("T1 alone: best %s eig %s" % (single["BestViewDirection"], single["EigenvalueSpectrum"]))
print("T1+AAL+BA: best %s eig %s (%.1f deg from T1 alone)" % (
    three["BestViewDirection"], three["EigenvalueSpectrum"],
    T.angle_deg(three["BestViewDirection"], single["BestViewDirection"], unsigned=True)))

# Through the helper, with the channels given explicitly (the volume shows only T1).
view, display = T.volume_view(merged, array=t1_name)
result = mce.apply_best_viewpoint(merged, view, Channels=[t1_name, aal_name, ba_name],
                                  OpacityFunction=None)
C.check(result.valid and T.angle_deg(result.best, three["BestViewDirection"]) < 1e-6,
        "apply_best_viewpoint with explicit Channels: the 3-channel direction")
cam = T.camera_direction(view)
C.check(T.angle_deg(cam, result.direction) < 0.01, "camera along the 3-channel direction")
shot = os.path.join(out, "multichannel_best.png")
SaveScreenshot(shot, view)
T.image_ok(mce, shot, C, "multichannel best")

# A real 65-channel volume: dipy's small_64D.nii (10^3 voxels x 65 diffusion volumes),
# read as one 65-component array (NIfTIImageReader, TimeAsVector on).
dwi_path = os.path.join(T.data_dir(), "small_64D.nii")
if os.path.exists(dwi_path):
    dwi = OpenDataFile(dwi_path)
    dwi.UpdatePipeline()
    name = dwi.PointData.keys()[0]
    C.check(dwi.PointData[name].GetNumberOfComponents() == 65,
            "small_64D.nii: one 65-component array")
    bvp = BestViewpoint(Input=dwi)
    msgs = T.Messages(bvp)
    bvp.UpdatePipeline()
    bvp.UpdatePropertyInformation()
    found = int(bvp.GetPropertyValue("NumberOfPointsFound"))
    C.check(int(bvp.GetPropertyValue("ViewValid")) == 1 and 0 < found < 2048 and
            bvp.GetDataInformation().GetNumberOfPoints() == found,
            "65 channels: valid view from all %d candidates (fewer than N)" % found)
    C.check(msgs.any_warning("fewer"), "65 channels: 'fewer than N' warning")
else:
    print("note: %s not found; 65-channel case skipped" % dwi_path)

# The Channels lists offer the channels only: after ResampleToImage (which adds
# vtkValidPointMask, and vtkGhostType under MPI) the three filters' lists and their
# defaults are the three atlases' arrays, not ParaView's bookkeeping arrays.
resampled = ResampleToImage(Input=merged)
resampled.SamplingDimensions = [40, 48, 40]
resampled.UpdatePipeline()
print("resampled arrays:", resampled.PointData.keys())
C.check("vtkValidPointMask" in resampled.PointData.keys(),
        "ResampleToImage adds vtkValidPointMask (what the lists must leave out)")
for make in (BestViewpoint, MultichannelFeatures, DimensionReduction):
    proxy = make(Input=resampled)
    domain = proxy.GetProperty("Channels").SMProperty.GetDomain("array_list")
    offered = [domain.GetString(i) for i in range(domain.GetNumberOfStrings())]
    label = proxy.GetXMLLabel()
    C.check(sorted(offered) == sorted(names), "%s offers the channels only: %s" % (label, offered))
    C.check(sorted(proxy.Channels) == sorted(names), "%s selects them by default: %s" % (label, list(proxy.Channels)))
    Delete(proxy)
Delete(resampled)

C.finish()
