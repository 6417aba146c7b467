"""Channels carry their names: readers name their array after the file, MergeChannels
names each channel after its file or keeps its label (unique), the Channels lists offer
channels only, the feature presets say what they mean per channel, and a single channel
gets advice.

Known answers:
- the real brain's three files merged: channels 'ch2', 'aal', 'brodmann' (each array's
  values those of its file); merged through ParaView's own MetaImageReader ("Meta File Series Reader") (array name
  'MetaImage' for every file): the same names, from the files; two files named ch2.nii.gz
  in two folders: 'ch2' and 'ch2_2'; a 65-component array keeps its name;
- MergeChannels' grid error names the files;
- the Channels lists of DimensionReduction after MultichannelFeatures, and of BestViewpoint
  after DimensionReduction, hold the three channels only (no Features, Foreground,
  ReducedCoordinates);
- presets on the 65-channel small_64D.nii: 6D gives 130 features, 24D 520, Custom with
  intensity alone 65, and the information property NumberOfFeatures says so; the
  enumeration entries explain 6D and 24D per channel; FeatureSet='6D' and '24D' still
  work;
- one channel (ch2 alone): MultichannelFeatures and DimensionReduction warn once per update
  that there is one channel and say to merge channels or open a multichannel file.
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkIOImage import vtkMetaImageWriter  # noqa: E402
import numpy as np  # noqa: E402

T.load_plugin(globals())
C = T.Checker("test_channel_names")
out = T.fresh_output_dir("channel_names")


def values(image, name):
    array = image.GetPointData().GetArray(name)
    return vtk_to_numpy(array) if array is not None else None


files = ["ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"]
readers = [simple.OpenDataFile(T.data_file(f)) for f in files]
sources = [T.output_of(r) for r in readers]
names = [s.GetPointData().GetScalars().GetName() for s in sources]
C.check(names == ["ch2", "aal", "brodmann"], "the readers name each array after its file: %s"
        % names)

merged = simple.MergeChannels(Input=readers)
msgs = T.Messages(merged)
image = T.output_of(merged)
got = [image.GetPointData().GetArrayName(i) for i in range(image.GetPointData().GetNumberOfArrays())]
C.check(got == ["ch2", "aal", "brodmann"] and not msgs.errors,
        "MergeChannels on the real brain: channels %s" % got)
C.check(all(np.array_equal(values(image, n), values(s, n)) for n, s in zip(names, sources)),
        "each merged channel holds its file's voxels")

# ParaView's own MetaImageReader ("Meta File Series Reader") names every array 'MetaImage': the channel is named after
# the file it was read from.
metas = []
for name, source in zip(("ch2", "aal", "brodmann"), sources):
    writer = vtkMetaImageWriter()
    writer.SetInputData(source)
    writer.SetFileName(os.path.join(out, name + ".mhd"))
    writer.SetRAWFileName(os.path.join(out, name + ".raw"))
    writer.SetCompression(False)
    writer.Write()
    metas.append(simple.MetaFileSeriesReader(FileNames=[os.path.join(out, name + ".mhd")]))
generic = [T.output_of(m).GetPointData().GetScalars().GetName() for m in metas]
C.check(generic == ["MetaImage"] * 3, "ParaView's MetaImageReader names them %s" % generic)
from_files = simple.MergeChannels(Input=metas)
image = T.output_of(from_files)
got = [image.GetPointData().GetArrayName(i) for i in range(image.GetPointData().GetNumberOfArrays())]
C.check(got == ["ch2", "aal", "brodmann"],
        "MergeChannels of 'MetaImage' arrays: named after their files %s" % got)
C.check(np.array_equal(values(image, "aal"), values(sources[1], "aal")),
        "the 'aal' channel holds the AAL voxels")

# Two files of the same name in two folders: unique names.
other = os.path.join(out, "other")
os.makedirs(other)
shutil.copyfile(T.data_file("ch2.nii.gz"), os.path.join(other, "ch2.nii.gz"))
twice = simple.MergeChannels(Input=[readers[0], simple.OpenDataFile(os.path.join(other, "ch2.nii.gz")),
                                    readers[1]])
image = T.output_of(twice)
got = [image.GetPointData().GetArrayName(i) for i in range(image.GetPointData().GetNumberOfArrays())]
C.check(got == ["ch2", "ch2_2", "aal"], "two files named ch2: %s" % got)
# The generic name twice (ParaView's reader on the same file twice): 'ch2', 'ch2_2'.
same = simple.MergeChannels(Input=[metas[0], simple.MetaFileSeriesReader(
    FileNames=[os.path.join(out, "ch2.mhd")])])
image = T.output_of(same)
got = [image.GetPointData().GetArrayName(i) for i in range(image.GetPointData().GetNumberOfArrays())]
C.check(got == ["ch2", "ch2_2"], "one .mhd twice through ParaView's reader: %s" % got)

# A time series through ParaView's reader: one name at every step, the series'.
for step, name in enumerate(("ch2", "aal")):  # headers naming ch2.raw, aal.raw beside them
    shutil.copyfile(os.path.join(out, name + ".mhd"), os.path.join(out, "s_%d.mhd" % step))
timed = simple.MergeChannels(Input=[simple.MetaFileSeriesReader(
    FileNames=[os.path.join(out, "s_0.mhd"), os.path.join(out, "s_1.mhd")]), readers[2]])
for step, name, source in ((0, "ch2", sources[0]), (1, "aal", sources[1])):
    timed.UpdatePipeline(step)
    image = timed.GetClientSideObject().GetOutputDataObject(0)
    got = [image.GetPointData().GetArrayName(i)
           for i in range(image.GetPointData().GetNumberOfArrays())]
    C.check(got == ["s", "brodmann"] and np.array_equal(values(image, "s"), values(source, name)),
            "a series s_0.mhd, s_1.mhd merged, time %d: channels %s, 's' holds %s" % (step, got, name))

# A multichannel array keeps its name (its label) when merged.
dwi_path = T.data_file("small_64D.nii")
dwi = simple.OpenDataFile(dwi_path)
dwi_image = T.output_of(dwi)
C.check(dwi_image.GetPointData().GetScalars().GetName() == "small_64D" and
        dwi_image.GetPointData().GetScalars().GetNumberOfComponents() == 65,
        "small_64D.nii: one 65-component array 'small_64D'")

# The grid error names the files.
bad = simple.MergeChannels(Input=[readers[0], dwi])
msgs = T.Messages(bad)
bad.UpdatePipeline()
C.check(msgs.any_error("not on one grid", "file '%s'" % dwi_path,
                       "file '%s'" % T.data_file("ch2.nii.gz"), "'small_64D'", "'ch2'"),
        "the grid error names both files and their channels: %s" % msgs.errors[:1])
simple.Delete(bad)

# ---- The Channels lists offer channels only ----------------------------------------------
# A filter made before its input ran (as a script does in the GUI): its Channels property
# gets every channel once the input has run, as the filter uses them, instead of staying
# empty (shown as every channel unchecked in the GUI's list).
early_merge = simple.MergeChannels(Input=[simple.OpenDataFile(T.data_file(f)) for f in files])
early = simple.MultichannelFeatures(Input=early_merge)
before = list(early.Channels)
early_merge.UpdatePipeline()
after = list(early.Channels)
print("Channels of a filter made before its input ran: %s, then %s" % (before, after))
C.check(before == [] and sorted(after) == ["aal", "brodmann", "ch2"],
        "a filter made before its input ran (Channels %s) selects every channel once it has: %s"
        % (before, after))
simple.Delete(early)
# paraview.simple first connects a new filter to the active source, then to its Input: the
# channels follow the input (a one-array active source left only the active array before).
wavelet = simple.Wavelet()
wavelet.UpdatePipeline()
simple.SetActiveSource(wavelet)
late = simple.MultichannelFeatures(Input=early_merge)
C.check(sorted(late.Channels) == ["aal", "brodmann", "ch2"],
        "a filter made while another source is active selects its input's channels: %s"
        % list(late.Channels))
simple.Delete(late)


def offered_channels(proxy):
    """The arrays the Channels property of `proxy` offers (its array_list domain)."""
    domain = proxy.GetProperty("Channels").SMProperty.GetDomain("array_list")
    return [domain.GetString(i) for i in range(domain.GetNumberOfStrings())]


features = simple.MultichannelFeatures(Input=merged, FeatureSet="6D")
features.UpdatePipeline()
reduction = simple.DimensionReduction(Input=features)
offered = offered_channels(reduction)
# (ParaView's array lists are sorted by name.)
C.check(offered == ["aal", "brodmann", "ch2"],
        "DimensionReduction after MultichannelFeatures offers the channels only: %s" % offered)
C.check(list(reduction.Channels) == ["aal", "brodmann", "ch2"],
        "... and selects them all: %s" % list(reduction.Channels))
reduction.ReferenceSampleSize = 300
reduction.UpdatePipeline()
viewpoint = simple.BestViewpoint(Input=reduction)
offered = offered_channels(viewpoint)
C.check(offered == ["aal", "brodmann", "ch2"],
        "BestViewpoint after DimensionReduction offers the channels only: %s" % offered)
for proxy in (viewpoint, reduction, features):
    simple.Delete(proxy)

# ---- Presets per channel ----------------------------------------------------------------
probe = simple.MultichannelFeatures(Input=dwi)
enum = probe.GetProperty("FeatureSet").SMProperty.GetDomain("enum")
entries = dict((enum.GetEntryText(i), enum.GetInfoText(i)) for i in range(enum.GetNumberOfEntries()))
print("FeatureSet entries:", entries)
C.check("2 per channel" in (entries.get("6D") or "") and "8 per channel" in (entries.get("24D") or ""),
        "the 6D and 24D entries say what they mean per channel: %s" % entries)
simple.Delete(probe)
for preset, props, expected in (("6D", {}, 130), ("24D", {}, 520),
                                ("Custom", {"Intensity": 1, "GradientMagnitude": 0}, 65)):
    f = simple.MultichannelFeatures(Input=dwi, FeatureSet=preset, MaskBackground=0, **props)
    f.UpdatePipeline()
    f.UpdatePropertyInformation()
    counted = int(f.GetPropertyValue("NumberOfFeatures"))
    components = T.output_of(f).GetPointData().GetArray("Features").GetNumberOfComponents()
    C.check(counted == expected and components == expected,
            "%s on 65 channels: %d features (NumberOfFeatures %d, Features has %d components)"
            % (preset, expected, counted, components))
    C.check(f.FeatureSet == preset, "FeatureSet reads back as %r (%r)" % (preset, f.FeatureSet))
    simple.Delete(f)

# ---- One channel: a warning that says what to do, once per update -----------------------
for make, props in ((simple.MultichannelFeatures, {"FeatureSet": "6D"}),
                    (simple.DimensionReduction, {"FeatureSet": "6D", "ReferenceSampleSize": 300})):
    f = make(Input=readers[0], **props)
    msgs = T.Messages(f)
    f.UpdatePipeline()
    advice = [w for w in msgs.warnings if "Only one channel" in w]
    print("warnings:", msgs.warnings)
    C.check(len(advice) == 1 and all(w in advice[0] for w in ("'ch2'", "Merge Channels",
                                                               "multichannel file")),
            "%s on ch2 alone: one warning naming the channel and saying to merge channels or "
            "open a multichannel file" % f.GetXMLLabel())
    f.Normalization = "MinMax"  # another run
    f.UpdatePipeline()
    advice = [w for w in msgs.warnings if "Only one channel" in w]
    C.check(len(advice) == 2, "%s: said again on the next update (%d)" % (f.GetXMLLabel(),
                                                                         len(advice)))
    simple.Delete(f)
f = simple.MultichannelFeatures(Input=merged)
msgs = T.Messages(f)
f.UpdatePipeline()
C.check(not any("Only one channel" in w for w in msgs.warnings), "three channels: no such warning")

C.finish()
