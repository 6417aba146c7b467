"""The OME-Zarr reader on the real 3-channel brain, written with python3-zarr.

Every channel is compared bit for bit with the NIfTI volumes it was written from, at both
resolution levels; spacing, origin, channel names, colours and units against what the
metadata says; the t axis as time steps (count, values, and each update reading only its
own time point's chunks); every compressor (blosc, zlib, gzip, none), both dimension
separators, big-endian and float dtypes, Fortran order, 2D and channel-less images; the
default resolution level under a memory limit; a sub-extent reading only its own chunks;
a missing chunk reading as the fill value; OpenDataFile choosing the reader for a folder.
"""
import glob
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

T.load_plugin({})
import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

import omezarr_testing as Z  # noqa: E402

C = T.Checker("test_omezarr_reader")
OUT = T.fresh_output_dir("omezarr_reader")


def read(folder, level=None, time=None, extent=None):
    """The reader's output (the server-side object's, in pvbatch's built-in session)."""
    reader = simple.OpenDataFile(folder)
    if level is not None:
        reader.ResolutionLevel = level
    reader.UpdatePipelineInformation()
    vtk_reader = reader.GetClientSideObject()
    if extent is not None:
        vtk_reader.UpdateExtent(extent)
        image = vtk_reader.GetOutputDataObject(0)
    else:
        reader.UpdatePipeline(time) if time is not None else reader.UpdatePipeline()
        image = vtk_reader.GetOutputDataObject(0)
    out = image.NewInstance()
    out.DeepCopy(image)
    return reader, out


channels_of = T.volume_arrays
field_strings = T.field_strings


def field_value(image, name):
    a = image.GetFieldData().GetArray(name)
    return None if a is None else a.GetValue(0)


def chunk_bytes(level_folder, keep=lambda key: True):
    """Bytes of the chunk files of one level (their keys relative to the level's folder)."""
    total = 0
    for path in glob.glob(os.path.join(level_folder, "**", "*"), recursive=True):
        key = os.path.relpath(path, level_folder)
        if os.path.isfile(path) and not os.path.basename(path).startswith(".") and keep(key):
            total += os.path.getsize(path)
    return total


def xyz(v):
    """NGFF (z, y, x) -> VTK (x, y, z)."""
    return [v[2], v[1], v[0]]


brain = Z.brain_arrays()  # (3, 181, 217, 181) uint8: c, z, y, x
C.check(brain.shape == (3, 181, 217, 181) and brain.dtype == np.uint8,
        "the source brain is 3 x 181 x 217 x 181 uint8 (%s %s)" % (brain.shape, brain.dtype))

# --- 1. Two levels, c z y x, blosc, "." separator, 64^3 chunks.
folder, levels, scales, translations = Z.brain_image(
    os.path.join(OUT, "brain.ome.zarr"), brain, chunks=(1, 64, 64, 64))
reader, image = read(folder)
C.check(reader.GetXMLName() == "OMEZarrReader",
        "OpenDataFile picks the OME-Zarr reader for a .ome.zarr folder (%s)" % reader.GetXMLName())
reader.UpdatePropertyInformation()
C.check(reader.GetPropertyValue("NumberOfLevels") == 2 and
        reader.GetPropertyValue("LevelRead") == 0,
        "2 levels, the default reads level 0 (it fits): NumberOfLevels %s, LevelRead %s"
        % (reader.GetPropertyValue("NumberOfLevels"), reader.GetPropertyValue("LevelRead")))
for level in (0, 1):
    if level == 1:
        reader, image = read(folder, level=1)
    got = channels_of(image)
    C.check(list(got) == Z.LABELS, "level %d: arrays named after omero labels %s" % (level, list(got)))
    expected = levels[level]
    for c, name in enumerate(Z.LABELS):
        a = got.get(name)
        C.check(a is not None and a.dtype == np.uint8 and np.array_equal(a, expected[c]),
                "level %d: %s equals the source bit for bit (%s voxels)"
                % (level, name, None if a is None else a.shape))
    C.check(np.allclose(image.GetSpacing(), xyz(scales[level][1:]), rtol=0, atol=1e-12),
            "level %d: spacing %s = the written scale (x, y, z) %s"
            % (level, image.GetSpacing(), xyz(scales[level][1:])))
    C.check(np.allclose(image.GetOrigin(), xyz(translations[level][1:]), rtol=0, atol=1e-12),
            "level %d: origin %s = the written translation %s"
            % (level, image.GetOrigin(), xyz(translations[level][1:])))
    C.check(field_value(image, "BytesRead") == chunk_bytes(os.path.join(folder, str(level))),
            "level %d: BytesRead %s = the bytes of all its chunk files %d"
            % (level, field_value(image, "BytesRead"), chunk_bytes(os.path.join(folder, str(level)))))
    C.check(field_value(image, "ResolutionLevel") == level,
            "level %d: field data ResolutionLevel %s" % (level, field_value(image, "ResolutionLevel")))
C.check(field_strings(image, "LengthUnit") == ["micrometer"],
        "LengthUnit from the axes' unit: %s" % field_strings(image, "LengthUnit"))
C.check(field_strings(image, "ChannelColors") == Z.COLORS,
        "ChannelColors from omero: %s" % field_strings(image, "ChannelColors"))
C.check(len(reader.TimestepValues) == 0, "no t axis: no time steps (%s)" % list(reader.TimestepValues))

# The default level under a memory limit: level 0 (21.3 MB) does not fit 10 MiB, level 1
# (2.7 MB) does; under 1 MiB neither does.
os.environ["MCV_MEMORY_LIMIT_MB"] = "10"
reader, image = read(folder)
reader.UpdatePropertyInformation()
C.check(reader.GetPropertyValue("LevelRead") == 1 and image.GetDimensions() == (91, 109, 91),
        "under 10 MiB the default reads level 1: LevelRead %s, dimensions %s"
        % (reader.GetPropertyValue("LevelRead"), image.GetDimensions()))
os.environ["MCV_MEMORY_LIMIT_MB"] = "1"
reader = simple.OMEZarrReader()  # observed before it reads the folder's metadata
msgs = T.Messages(reader)
reader.FileName = folder
reader.UpdatePipeline()
C.check(msgs.any_error(folder, "no resolution level that fits in memory", "level 1"),
        "under 1 MiB: an error naming the folder and the coarsest level (%s)" % msgs.errors[:1])
C.check(reader.GetDataInformation().GetNumberOfPoints() == 0, "... and no points")
del os.environ["MCV_MEMORY_LIMIT_MB"]

# A sub-extent reads only the chunks that meet it: x 70..129, y 10..60, z 100..180.
extent = (70, 129, 10, 60, 100, 180)
reader, image = read(folder, level=0, extent=extent)
got = channels_of(image)
crop = brain[:, 100:181, 10:61, 70:130]
C.check(image.GetExtent() == extent and
        all(np.array_equal(got[n], crop[c]) for c, n in enumerate(Z.LABELS)),
        "extent %s: values equal the source's crop (%s)" % (extent, image.GetExtent()))


def meets(key):
    c, z, y, x = (int(v) for v in key.split("."))
    return (z * 64 <= 180 and z * 64 + 63 >= 100 and y * 64 <= 60 and y * 64 + 63 >= 10 and
            x * 64 <= 129 and x * 64 + 63 >= 70)


expected_bytes = chunk_bytes(os.path.join(folder, "0"), meets)
C.check(field_value(image, "BytesRead") == expected_bytes,
        "extent %s: BytesRead %s = the bytes of the chunks it meets (%d of %d)"
        % (extent, field_value(image, "BytesRead"), expected_bytes,
           chunk_bytes(os.path.join(folder, "0"))))

# --- 2. t c z y x: 3 time points, zlib, "/" separator.
folder, levels, scales, translations = Z.brain_image(
    os.path.join(OUT, "brain_t.zarr"), brain, axes="tczyx", time_points=3,
    chunks=(1, 1, 64, 64, 64), compressor="zlib", separator="/")
reader = simple.OpenDataFile(folder)
reader.UpdatePipelineInformation()
C.check(reader.GetXMLName() == "OMEZarrReader", "OpenDataFile picks the reader for a .zarr folder")
steps = list(reader.TimestepValues)
C.check(steps == [10.0, 12.5, 15.0], "time steps from the t scale/translation: %s" % steps)
for k in (2, 0, 1):
    reader, image = read(folder, time=steps[k])
    got = channels_of(image)
    C.check(all(a.dtype == np.uint16 and np.array_equal(a, levels[0][k][c])
                for c, a in enumerate(got.values())) and len(got) == 3,
            "time %g: the 3 channels of time point %d equal the source (uint16)" % (steps[k], k))
    C.check(image.GetInformation().Get(image.DATA_TIME_STEP()) == steps[k],
            "time %g: DATA_TIME_STEP %s" % (steps[k], image.GetInformation().Get(image.DATA_TIME_STEP())))
    own = chunk_bytes(os.path.join(folder, "0"), lambda key: key.split("/")[0] == str(k))
    C.check(field_value(image, "BytesRead") == own,
            "time %g: BytesRead %s = the chunks of time point %d only (%d of %d)"
            % (steps[k], field_value(image, "BytesRead"), k, own,
               chunk_bytes(os.path.join(folder, "0"))))
C.check(field_strings(image, "TimeUnit") == ["second"], "TimeUnit %s" % field_strings(image, "TimeUnit"))
reader, image = read(folder, level=1, time=steps[1])
got = channels_of(image)
C.check(all(np.array_equal(a, levels[1][1][c]) for c, a in enumerate(got.values())),
        "level 1, time point 1: equal to the source")

# --- 3. Encodings, on a crop of the brain (z 80..119, y 60..159, x 40..139) with odd chunks.
small = brain[:, 80:120, 60:160, 40:140]
variants = [
    ("gzip", dict(compressor="gzip")),
    ("none", dict(compressor="none")),
    ("blosc_slash", dict(compressor="blosc", separator="/")),
    ("be_u2", dict(dtype=">u2")),
    ("le_i2", dict(dtype="<i2", compressor="zlib")),
    ("le_f4", dict(dtype="<f4")),
    ("be_f8", dict(dtype=">f8", compressor="gzip")),
    ("fortran", dict(order="F", dtype="<u2")),
    ("fortran_be_f4", dict(order="F", dtype=">f4", compressor="none")),
]
for name, options in variants:
    folder = Z.write_image(os.path.join(OUT, name + ".ome.zarr"), [small],
                           scales=[[1, 2, 2, 2]], chunks=(2, 17, 33, 40), **options)
    reader, image = read(folder)
    got = channels_of(image)
    want = small.astype(options.get("dtype", np.uint8))
    C.check(len(got) == 3 and all(np.array_equal(a, want[c]) and
                                  a.dtype == want.dtype.newbyteorder("=")
                                  for c, a in enumerate(got.values())),
            "%s: every channel equals the source (%s, %s)"
            % (name, [str(a.dtype) for a in got.values()], image.GetDimensions()))

# 2D y x, one channel, no omero: one slice, named C1.
folder = Z.write_image(os.path.join(OUT, "slice.ome.zarr"), [small[0, 20]], axes="yx",
                       scales=[[0.25, 0.5]], translations=[[3.0, 4.0]], chunks=(30, 30),
                       labels=None)
reader, image = read(folder)
got = channels_of(image)
C.check(list(got) == ["C1"] and image.GetDimensions() == (100, 100, 1) and
        np.array_equal(got["C1"][0], small[0, 20]),
        "y x image: one slice, one array C1 equal to the source (%s, %s)"
        % (list(got), image.GetDimensions()))
C.check(image.GetSpacing()[:2] == (0.5, 0.25) and image.GetOrigin()[:2] == (4.0, 3.0),
        "y x image: spacing %s origin %s" % (image.GetSpacing(), image.GetOrigin()))

# z y x without c, with a multiscale-level scale applied after the dataset's; duplicate
# labels made unique.
folder = Z.write_image(os.path.join(OUT, "zyx.ome.zarr"), [small[1]], axes="zyx",
                       scales=[[1.0, 2.0, 3.0]], chunks=(16, 16, 16), labels=["AAL"],
                       multiscale_scale=[0.5, 0.5, 0.5])
reader, image = read(folder)
got = channels_of(image)
C.check(list(got) == ["AAL"] and np.array_equal(got["AAL"], small[1]),
        "z y x image: one array named from omero, equal to the source (%s)" % list(got))
C.check(np.allclose(image.GetSpacing(), (1.5, 1.0, 0.5)),
        "multiscale scale applied after the level's: spacing %s" % (image.GetSpacing(),))
folder = Z.write_image(os.path.join(OUT, "dup.ome.zarr"), [small], scales=[[1, 1, 1, 1]],
                       chunks=(3, 40, 100, 100), labels=["A", "A", ""])
reader, image = read(folder)
C.check(list(channels_of(image)) == ["A", "A (2)", "C3"],
        "duplicate and empty labels: unique names %s" % list(channels_of(image)))

# --- 4. A missing chunk is the fill value.
folder = Z.write_image(os.path.join(OUT, "missing.ome.zarr"), [small], scales=[[1, 1, 1, 1]],
                       chunks=(1, 20, 50, 50), fill_value=7)
os.remove(os.path.join(folder, "0", "1.1.0.1"))  # channel 1, z 20..39, y 0..49, x 50..99
reader, image = read(folder)
got = channels_of(image)
want = small.copy()
want[1, 20:40, 0:50, 50:100] = 7
C.check(all(np.array_equal(a, want[c]) for c, a in enumerate(got.values())),
        "a missing chunk reads as the fill value 7, the rest as the source")

C.finish()
