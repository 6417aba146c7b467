"""Time series of NIfTI and MetaImage files: a list of files (and ParaView's grouping of
numbered files) is one reader whose time step i is file i.

Known answers:
- the real brain's three volumes (Colin27 ch2, the AAL and Brodmann atlases, one grid)
  copied as vol_0.nii.gz, vol_1.nii.gz, vol_2.nii.gz and opened with OpenDataFile(list):
  NIfTIImageReader, TimestepValues [0, 1, 2], the voxels of step i bit for bit those of
  file i, the array named "vol" at every step (named after the series);
- three hand-written .mha files (4 x 3 x 2 uint16, voxel v of file t = 1000 t + v) through
  CheckedMetaImageReader: the same, array "t";
- one file: no time steps, the array named after the file ("ch2");
- a series whose second file has another grid (a 20^3 NIfTI after ch2, a 5 x 3 x 2 .mha
  after 4 x 3 x 2 ones): step 0 read, step 1 an error naming the file, its grid, the first
  file and its grid, 0 points; a truncated file in a series: an error naming it, 0 points;
- state files: a saved state with a series reloads with its files and time steps; a state
  in the form the single-file readers wrote (FileName with one element, TimeAsVector)
  loads.
"""
import os
import shutil
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy as np  # noqa: E402

T.load_plugin(globals())
C = T.Checker("test_time_series")
out = T.fresh_output_dir("time_series")


def path(name):
    return os.path.join(out, name)


def voxels_at(proxy, time=None):
    """(array name, numpy copy of the point scalars, number of points) of `proxy` at `time`."""
    if time is None:
        proxy.UpdatePipeline()
    else:
        proxy.UpdatePipeline(time)
    image = proxy.GetClientSideObject().GetOutputDataObject(0)
    scalars = image.GetPointData().GetScalars() if image is not None else None
    if scalars is None:
        return None, None, image.GetNumberOfPoints() if image is not None else 0
    return scalars.GetName(), vtk_to_numpy(scalars).copy(), image.GetNumberOfPoints()


def timesteps(proxy):
    proxy.UpdatePipelineInformation()
    return list(proxy.TimestepValues) if proxy.TimestepValues is not None else []


# ---- NIfTI: the real brain as a series --------------------------------------------------
sources = ["ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"]
series = []
for i, name in enumerate(sources):
    series.append(path("vol_%d.nii.gz" % i))
    shutil.copyfile(T.data_file(name), series[-1])
expected = []
for name in sources:
    single = NIfTIImageReader(FileName=T.data_file(name))  # noqa: F821 (load_plugin)
    got_name, values, _ = voxels_at(single)
    expected.append(values)
    C.check(got_name == name.split(".")[0] and timesteps(single) == [],
            "%s alone: array named after the file (%r), no time steps" % (name, got_name))
    simple.Delete(single)

reader = simple.OpenDataFile(series)
msgs = T.Messages(reader)
C.check(reader.GetXMLName() == "NIfTIImageReader",
        "OpenDataFile(3 .nii.gz files): NIfTIImageReader (%s)" % reader.GetXMLName())
C.check(list(reader.FileName) == series, "FileName holds the 3 files in order")
C.check(timesteps(reader) == [0.0, 1.0, 2.0], "TimestepValues %s" % timesteps(reader))
for t in (0, 1, 2, 0):  # and back to the first
    got_name, values, n = voxels_at(reader, t)
    C.check(got_name == "vol" and values is not None and values.dtype == expected[t].dtype and
            np.array_equal(values, expected[t]),
            "NIfTI series, time %d: the voxels of %s bit for bit, array 'vol' (%r, %d points)"
            % (t, sources[t], got_name, n))
C.check(not msgs.errors, "NIfTI series: no error (%s)" % msgs.errors[:1])

# The GUI's group of numbered files goes through the same property (pqLoadDataReaction
# sets every file of the group on the reader's repeatable FileName property).
grouped = NIfTIImageReader(FileName=series[:2])  # noqa: F821
C.check(timesteps(grouped) == [0.0, 1.0], "NIfTIImageReader(FileName=[2 files]): 2 steps")
simple.Delete(grouped)


# ---- MetaImage: hand-written .mha files -------------------------------------------------
def write_mha(name, dims, values, spacing=(1.0, 1.0, 1.0)):
    header = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
              "ElementSpacing = %g %g %g\nDimSize = %d %d %d\nElementType = MET_USHORT\n"
              "ElementDataFile = LOCAL\n" % (tuple(spacing) + tuple(dims)))
    with open(path(name), "wb") as f:
        f.write(header.encode())
        f.write(struct.pack("<%dH" % len(values), *values))
    return path(name)


mha = [write_mha("t_%d.mha" % t, (4, 3, 2), [1000 * t + v for v in range(24)]) for t in range(3)]
meta = simple.OpenDataFile(mha)
msgs = T.Messages(meta)
C.check(meta.GetXMLName() == "CheckedMetaImageReader",
        "OpenDataFile(3 .mha files): CheckedMetaImageReader (%s)" % meta.GetXMLName())
C.check(timesteps(meta) == [0.0, 1.0, 2.0], "MetaImage TimestepValues %s" % timesteps(meta))
for t in (2, 0, 1):
    got_name, values, n = voxels_at(meta, t)
    C.check(got_name == "t" and values is not None and
            values.tolist() == [1000 * t + v for v in range(24)],
            "MetaImage series, time %d: voxel v = 1000 t + v, array 't' (%r)" % (t, got_name))
C.check(not msgs.errors, "MetaImage series: no error (%s)" % msgs.errors[:1])
single = simple.CheckedMetaImageReader(FileName=mha[1])
got_name, values, _ = voxels_at(single)
C.check(got_name == "t_1" and timesteps(single) == [] and values.tolist()[0] == 1000,
        "one .mha: array 't_1', no time steps")
simple.Delete(single)


# ---- Series of files on different grids, and a bad file in a series ----------------------
def nifti_20(name):
    """A valid 20^3 float32 NIfTI (the header of test_nifti_reader)."""
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, 20, 20, 20, 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, 16, 32)
    struct.pack_into("<8f", h, 76, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    struct.pack_into("<f", h, 108, 352.0)
    struct.pack_into("<f", h, 112, 1.0)
    h[344:348] = b"n+1\0"
    with open(path(name), "wb") as f:
        f.write(bytes(h) + struct.pack("<8000f", *range(8000)))
    return path(name)


small = nifti_20("small_1.nii")
for label, files, first_grid, other_grid in (
        ("NIfTI", [series[0], small], "181 x 217 x 181", "20 x 20 x 20"),
        ("MetaImage", [mha[0], write_mha("odd_1.mha", (5, 3, 2), list(range(30)))],
         "4 x 3 x 2", "5 x 3 x 2")):
    mixed = simple.OpenDataFile(files)
    msgs = T.Messages(mixed)
    _, values, n0 = voxels_at(mixed, 0)
    C.check(n0 > 0 and not msgs.errors, "%s series of two grids: step 0 read (%d points)"
            % (label, n0))
    _, values, n1 = voxels_at(mixed, 1)
    print("errors:", msgs.errors)
    C.check(msgs.any_error(os.path.basename(files[1]), other_grid, "first file of its time series",
                           os.path.basename(files[0]), first_grid, "one grid"),
            "%s series of two grids: step 1 is an error naming the file, both grids and the "
            "first file" % label)
    C.check(n1 == 0, "%s series of two grids: step 1 has 0 points (%d)" % (label, n1))
    simple.Delete(mixed)

cut = path("vol_cut_1.nii.gz")
with open(series[1], "rb") as f:
    data = f.read()
with open(cut, "wb") as f:
    f.write(data[:len(data) // 2])
broken = simple.OpenDataFile([series[0], cut, series[2]])
msgs = T.Messages(broken)
_, values, n = voxels_at(broken, 1)
C.check(msgs.any_error("vol_cut_1.nii.gz", "gzip") and n == 0,
        "a cut file at step 1: an error naming it, 0 points (%s)" % msgs.errors[:1])
msgs.clear()
_, values, n = voxels_at(broken, 2)
C.check(not msgs.errors and np.array_equal(values, expected[2]),
        "the step after the cut file: read again, the Brodmann voxels")
simple.Delete(broken)

# ---- State files --------------------------------------------------------------------------
state = path("series.pvsm")
simple.SaveState(state)
simple.ResetSession()
T.load_plugin(globals())
simple.LoadState(state)
reloaded = [p for p in simple.GetSources().values() if p.GetXMLName() == "NIfTIImageReader"]
C.check(len(reloaded) == 1 and list(reloaded[0].FileName) == series and
        timesteps(reloaded[0]) == [0.0, 1.0, 2.0],
        "a saved state reloads the series reader with its 3 files and 3 time steps")
if reloaded:
    got_name, values, _ = voxels_at(reloaded[0], 1)
    C.check(got_name == "vol" and np.array_equal(values, expected[1]),
            "reloaded series, time 1: the AAL voxels")
simple.ResetSession()
T.load_plugin(globals())

# The state of a single-file reader as the plugin wrote it before the readers read series
# (FileName with one element, TimeAsVector on the reader itself).
old_state = path("single_file_reader.pvsm")
with open(old_state, "w") as f:
    f.write("""<ParaView>
  <ServerManagerState version="5.11.0">
    <Proxy group="sources" type="NIfTIImageReader" id="8000" servers="1">
      <Property name="FileName" id="8000.FileName" number_of_elements="1">
        <Element index="0" value="%s"/>
        <Domain name="files" id="8000.FileName.files"/>
      </Property>
      <Property name="TimeAsVector" id="8000.TimeAsVector" number_of_elements="1">
        <Element index="0" value="0"/>
        <Domain name="bool" id="8000.TimeAsVector.bool"/>
      </Property>
    </Proxy>
    <Proxy group="filters" type="MultichannelFeatures" id="8001" servers="1">
      <Property name="Input" id="8001.Input" number_of_elements="1">
        <Proxy value="8000" output_port="0"/>
      </Property>
      <Property name="FeatureSet" id="8001.FeatureSet" number_of_elements="1">
        <Element index="0" value="1"/>
      </Property>
    </Proxy>
    <ProxyCollection name="sources">
      <Item id="8000" name="ch2.nii.gz"/>
      <Item id="8001" name="MultichannelFeatures1"/>
    </ProxyCollection>
  </ServerManagerState>
</ParaView>
""" % T.data_file("ch2.nii.gz"))
simple.LoadState(old_state)
old = simple.FindSource("ch2.nii.gz")
feats = simple.FindSource("MultichannelFeatures1")
C.check(old is not None and list(old.FileName) == [T.data_file("ch2.nii.gz")] and
        old.TimeAsVector == 0, "an old single-file state loads: FileName and TimeAsVector")
if old is not None:
    got_name, values, _ = voxels_at(old)
    C.check(got_name == "ch2" and np.array_equal(values, expected[0]),
            "the old state's reader reads ch2 (array 'ch2')")
C.check(feats is not None and feats.FeatureSet == "24D",
        "an old state's FeatureSet value 1 is 24D (%s)" % (feats.FeatureSet if feats else None))
if feats is not None:
    feats.UpdatePipeline()
    feats.UpdatePropertyInformation()
    C.check(int(feats.GetPropertyValue("NumberOfFeatures")) == 8,
            "the old state's features run: 8 on one channel")

C.finish()
