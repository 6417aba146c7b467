"""ImageJ hyperstacks and OME-TIFF files through the plugin's checked TIFF reader.

The files are written here with tifffile (Debian's python3-tifffile) from the real brain:
Colin27 ch2 (T1), AAL and Brodmann read with the plugin's NIfTI reader and taken every
second voxel (a 2 mm grid, 91 x 109 x 91). Checked, for each file, against what was
written:
- every channel is one point array (C1.. or the file's channel names) whose values equal the
  written ones bit for bit; the spacing is the written one; the unit is in the field data
  (LengthUnit, TimeUnit);
- frames are time steps (TimestepValues from finterval / TimeIncrement), and each time
  reads that frame (frame 1 = 2 x frame 0 + 1, or frame 0 + 1000);
- ImageJ ZCYX (uint16, 3 channels) and TZCYX (float32, 2 frames), uint8 with slice labels,
  zlib-compressed pages; a multi-page TIFF that is not ImageJ stays one array;
- OME-TIFF from tifffile in two DimensionOrders (XYZCT with PhysicalSize in nm and tiled
  pages; XYCZT), Bio-Formats style (hand-made OME-XML, one TiffData per plane, XYZTC order,
  a set of two files linked by UUID FileName, opened by its first file or by both); OpenDataFile picks the checked reader for
  .ome.tif and .ome.tiff;
- bad files, each an error naming the file and the problem, 0 points: images= other than
  channels x slices x frames, missing pages, an unknown unit, OME SizeC other than the
  Channel elements or the planes, a TiffData beyond the pages, an OME Type other than the
  pages', a file of a set missing, one frame larger than the memory (MCV_MEMORY_LIMIT_MB);
- the time keeper (the GUI's time) shows a hyperstack's time steps.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

import numpy as np  # noqa: E402
import tifffile  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_tiff_hyperstack")
OUT = T.fresh_output_dir("tiff_hyperstack")
NAMES = T.BRAIN


def path(name):
    return os.path.join(OUT, name)


volume_arrays = T.volume_arrays


def field_text(image, name):
    values = T.field_strings(image, name)
    return values[0] if values else None


# ---- the source: the real brain on a 2 mm grid ----------------------------------------
SOURCE = dict(zip(NAMES, T.brain_arrays(NAMES, step=2)))
Z, Y, X = SOURCE["ch2"].shape
C.check((X, Y, Z) == (91, 109, 91), "the brain on a 2 mm grid: %d x %d x %d" % (X, Y, Z))


def channels(dtype):
    """The three channels as (C, Z, Y, X) of a type: T1 scaled into uint8, the atlases as
    they are (their labels fit in uint16; modulo 256 in uint8)."""
    out = []
    for n in NAMES:
        v = SOURCE[n].astype(np.float64)
        if dtype == np.uint8:
            v = v * 255.0 / max(v.max(), 1) if n == "ch2" else np.mod(v, 256)
        out.append(v.astype(dtype))
    return np.stack(out)


def open_checked(files, **properties):
    proxy = simple.CheckedTIFFReader()
    msgs = T.Messages(proxy)
    for key, value in properties.items():
        setattr(proxy, key, value)
    proxy.FileNames = files if isinstance(files, list) else [files]
    return proxy, msgs


def output(proxy, time=None):
    if time is None:
        proxy.UpdatePipeline()
    else:
        proxy.UpdatePipeline(time)
    return proxy.GetClientSideObject().GetOutputDataObject(0)


def check_volume(label, proxy, msgs, expected, names, spacing, unit, times=None,
                 time_unit=None):
    """expected: (T, C, Z, Y, X) values written. Checks every frame and channel bit for bit,
    the names, spacing, units and time steps."""
    proxy.UpdatePipelineInformation()
    steps = [float(t) for t in proxy.TimestepValues] if times else []
    C.check(steps == (list(times) if times else []),
            "%s: time steps %s (expected %s)" % (label, steps, times))
    for f in range(expected.shape[0]):
        image = output(proxy, times[f] if times else None)
        got = volume_arrays(image)
        same = list(got.keys()) == list(names) and all(
            got[names[c]].dtype == expected.dtype and
            np.array_equal(got[names[c]], expected[f, c]) for c in range(len(names)))
        C.check(not msgs.errors and same and image.GetDimensions() == (X, Y, Z),
                "%s: frame %d, channels %s equal the written %s values bit for bit "
                "(got %s %s, errors %s)" % (label, f, list(names), expected.dtype,
                                            list(got.keys()), image.GetDimensions(),
                                            msgs.errors))
        got_spacing = image.GetSpacing()
        C.check(np.allclose(got_spacing, spacing, rtol=1e-12, atol=0),
                "%s: spacing %s (written %s)" % (label, got_spacing, spacing))
        C.check(field_text(image, "LengthUnit") == unit and
                (time_unit is None or field_text(image, "TimeUnit") == time_unit),
                "%s: LengthUnit %r TimeUnit %r" % (label, field_text(image, "LengthUnit"),
                                                   field_text(image, "TimeUnit")))
        if times:
            dt = image.GetInformation().Get(image.DATA_TIME_STEP())
            C.check(dt == times[f], "%s: frame %d has DATA_TIME_STEP %s" % (label, f, dt))


# ---- ImageJ hyperstacks -------------------------------------------------------------
# ZCYX, uint16, 3 channels; X/Y/Z spacing all different (so a swap would show).
zcyx = channels(np.uint16)                             # (C, Z, Y, X)
tifffile.imwrite(path("zcyx.tif"), np.ascontiguousarray(zcyx.transpose(1, 0, 2, 3)),
                 imagej=True, resolution=(1 / 2.0, 1 / 2.5),
                 metadata={"axes": "ZCYX", "spacing": 3.0, "unit": "um"})
proxy, msgs = open_checked(path("zcyx.tif"))
check_volume("ImageJ ZCYX uint16", proxy, msgs, zcyx[None], ["C1", "C2", "C3"],
             (2.0, 2.5, 3.0), "µm")
simple.Delete(proxy)

# TZCYX, float32, 2 frames, frame 1 = 2 x frame 0 + 1; finterval 0.5 s.
f0 = channels(np.float32)
tzcyx = np.stack([f0, 2 * f0 + 1])                      # (T, C, Z, Y, X)
tifffile.imwrite(path("tzcyx.tif"), np.ascontiguousarray(tzcyx.transpose(0, 2, 1, 3, 4)),
                 imagej=True, resolution=(1 / 2.0, 1 / 2.0),
                 metadata={"axes": "TZCYX", "spacing": 2.0, "unit": "um", "finterval": 0.5})
proxy, msgs = open_checked(path("tzcyx.tif"))
check_volume("ImageJ TZCYX float32", proxy, msgs, tzcyx, ["C1", "C2", "C3"],
             (2.0, 2.0, 2.0), "µm", times=[0.0, 0.5], time_unit="s")
# A time between steps reads the frame at or before it.
image = output(proxy, 0.4)
C.check(np.array_equal(volume_arrays(image)["C2"], tzcyx[0, 1]),
        "ImageJ TZCYX: time 0.4 reads frame 0")
simple.Delete(proxy)

# uint8 with slice labels (channel names), zlib-compressed pages, no finterval: times 0, 1.
u8 = channels(np.uint8)
tcz = np.stack([u8, u8 + 1])
labels = [NAMES[c] for t in range(2) for z in range(Z) for c in range(3)]
tifffile.imwrite(path("labels.tif"), np.ascontiguousarray(tcz.transpose(0, 2, 1, 3, 4)),
                 imagej=True, compression="zlib", resolution=(1 / 2.0, 1 / 2.0),
                 metadata={"axes": "TZCYX", "spacing": 2.0, "unit": "micron",
                           "Labels": labels})
C.check(tifffile.TiffFile(path("labels.tif")).pages[0].compression == 8,
        "labels.tif has zlib-compressed pages")
proxy, msgs = open_checked(path("labels.tif"))
check_volume("ImageJ TZCYX uint8, labels, zlib", proxy, msgs, tcz, list(NAMES),
             (2.0, 2.0, 2.0), "µm", times=[0.0, 1.0], time_unit="frame")
simple.Delete(proxy)

# A multi-page TIFF that is not ImageJ: one array, each page a slice.
tifffile.imwrite(path("plain.tif"), zcyx[0], photometric="minisblack")
proxy, msgs = open_checked(path("plain.tif"))
got = volume_arrays(output(proxy))
C.check(not msgs.errors and list(got.keys()) == ["Tiff Scalars"] and
        np.array_equal(got["Tiff Scalars"], zcyx[0]) and
        not proxy.TimestepValues,
        "a plain multi-page TIFF: one array 'Tiff Scalars', pages as slices (%s)"
        % list(got.keys()))
simple.Delete(proxy)

# ---- OME-TIFF ---------------------------------------------------------------------------
# tifffile, axes TCZYX (DimensionOrder XYZCT), float32, 2 frames (frame 1 = frame 0 + 1000),
# PhysicalSize in nm, TimeIncrement 2 s, channel names, tiled pages.
ome_t = np.stack([f0, f0 + 1000])                        # (T, C, Z, Y, X)
tifffile.imwrite(path("tczyx.ome.tif"), ome_t, ome=True, photometric="minisblack",
                 tile=(32, 32),
                 metadata={"axes": "TCZYX", "Channel": {"Name": list(NAMES)},
                           "PhysicalSizeX": 2000.0, "PhysicalSizeXUnit": "nm",
                           "PhysicalSizeY": 2500.0, "PhysicalSizeYUnit": "nm",
                           "PhysicalSizeZ": 3000.0, "PhysicalSizeZUnit": "nm",
                           "TimeIncrement": 2.0, "TimeIncrementUnit": "s"})
desc = tifffile.TiffFile(path("tczyx.ome.tif")).pages[0].description
C.check('DimensionOrder="XYZCT"' in desc and tifffile.TiffFile(
    path("tczyx.ome.tif")).pages[0].is_tiled, "tczyx.ome.tif: XYZCT, tiled pages")
proxy, msgs = open_checked(path("tczyx.ome.tif"))
check_volume("OME XYZCT float32 (nm, tiled)", proxy, msgs, ome_t, list(NAMES),
             (2.0, 2.5, 3.0), "µm", times=[0.0, 2.0], time_unit="s")
simple.Delete(proxy)

# tifffile, axes ZCYX (DimensionOrder XYCZT), uint16, µm, .ome.tiff.
tifffile.imwrite(path("zcyx.ome.tiff"), np.ascontiguousarray(zcyx.transpose(1, 0, 2, 3)),
                 ome=True, photometric="minisblack",
                 metadata={"axes": "ZCYX", "Channel": {"Name": ["T1", "AAL", "Brodmann"]},
                           "PhysicalSizeX": 2.0, "PhysicalSizeXUnit": "µm",
                           "PhysicalSizeY": 2.0, "PhysicalSizeYUnit": "µm",
                           "PhysicalSizeZ": 2.0, "PhysicalSizeZUnit": "µm"})
C.check('DimensionOrder="XYCZT"' in tifffile.TiffFile(path("zcyx.ome.tiff")).pages[0].description,
        "zcyx.ome.tiff: XYCZT")
proxy, msgs = open_checked(path("zcyx.ome.tiff"))
check_volume("OME XYCZT uint16", proxy, msgs, zcyx[None], ["T1", "AAL", "Brodmann"],
             (2.0, 2.0, 2.0), "µm")
simple.Delete(proxy)


def bioformats_xml(order, size_c, channel_names, tiff_data, unit="µm", extra=""):
    """OME-XML as Bio-Formats writes it (default namespace, TiffData per plane)."""
    chans = "".join('<Channel ID="Channel:0:%d" Name="%s" SamplesPerPixel="1"/>' % (i, n)
                    for i, n in enumerate(channel_names))
    return ('<?xml version="1.0" encoding="UTF-8"?>'
            '<OME xmlns="http://www.openmicroscopy.org/Schemas/OME/2016-06" '
            'Creator="OME Bio-Formats 6.x (hand-made in a test)">'
            '<Image ID="Image:0" Name="brain"><Pixels BigEndian="false" '
            'DimensionOrder="%s" ID="Pixels:0" Interleaved="false" '
            'PhysicalSizeX="0.002" PhysicalSizeXUnit="mm" PhysicalSizeY="0.002" '
            'PhysicalSizeYUnit="mm" PhysicalSizeZ="2" PhysicalSizeZUnit="%s" '
            'SignificantBits="16" SizeC="%d" SizeT="2" SizeX="%d" SizeY="%d" SizeZ="%d" '
            'TimeIncrement="1500" TimeIncrementUnit="ms" Type="uint16" %s>%s%s'
            '</Pixels></Image></OME>'
            % (order, unit, size_c, X, Y, Z, extra, chans, tiff_data))


def write_planes(name, planes, description):
    """One page per (Y, X) plane, the description on the first page only."""
    with tifffile.TiffWriter(name) as tif:
        for i, plane in enumerate(planes):
            tif.write(plane, photometric="minisblack", metadata=None,
                      description=description.encode("utf-8") if description and i == 0 else None)


# Bio-Formats style: XYZTC, one TiffData per plane (listed in reverse), 2 frames
# (frame 1 = frame 0 + 7), PhysicalSize X/Y in mm, TimeIncrement in ms.
bf = np.stack([zcyx, zcyx + 7])                          # (T, C, Z, Y, X)
order = [(c, t, z) for c in range(3) for t in range(2) for z in range(Z)]  # XYZTC
blocks = "".join('<TiffData FirstC="%d" FirstT="%d" FirstZ="%d" IFD="%d" PlaneCount="1"/>'
                 % (c, t, z, i) for i, (c, t, z) in reversed(list(enumerate(order))))
write_planes(path("bioformats.ome.tif"), [bf[t, c, z] for c, t, z in order],
             bioformats_xml("XYZTC", 3, NAMES, blocks))
proxy, msgs = open_checked(path("bioformats.ome.tif"))
check_volume("Bio-Formats XYZTC uint16", proxy, msgs, bf, list(NAMES), (2.0, 2.0, 2.0),
             "µm", times=[0.0, 1.5], time_unit="s")
simple.Delete(proxy)

# A set of two files, one frame each, linked by UUID FileName (the OME-XML in the first).
folder = path("set")
os.makedirs(folder, exist_ok=True)
blocks = "".join('<TiffData FirstT="%d" IFD="0" PlaneCount="%d"><UUID FileName="set_t%d.ome.tif">'
                 'urn:uuid:%d</UUID></TiffData>' % (t, 3 * Z, t, t) for t in range(2))
for t in range(2):
    write_planes(os.path.join(folder, "set_t%d.ome.tif" % t),
                 [bf[t, c, z] for z in range(Z) for c in range(3)],           # XYCZT
                 bioformats_xml("XYCZT", 3, NAMES, blocks) if t == 0 else None)
proxy, msgs = open_checked(os.path.join(folder, "set_t0.ome.tif"))
check_volume("OME file set (UUID FileName)", proxy, msgs, bf, list(NAMES), (2.0, 2.0, 2.0),
             "µm", times=[0.0, 1.5], time_unit="s")
simple.Delete(proxy)
# Both files of the set selected (as the GUI's file dialog groups them): the same image,
# not a time series of its parts.
proxy, msgs = open_checked([os.path.join(folder, "set_t%d.ome.tif" % t) for t in range(2)])
check_volume("OME file set, both files listed", proxy, msgs, bf, list(NAMES), (2.0, 2.0, 2.0),
             "µm", times=[0.0, 1.5], time_unit="s")
simple.Delete(proxy)

# Two series (images) in one file: the first is read, with a warning that says so.
with tifffile.TiffWriter(path("two_series.ome.tif"), ome=True) as tif:
    tif.write(zcyx, photometric="minisblack",
              metadata={"axes": "CZYX", "Channel": {"Name": list(NAMES)}})
    tif.write(zcyx[:, :10], photometric="minisblack", metadata={"axes": "CZYX"})
proxy, msgs = open_checked(path("two_series.ome.tif"))
got = volume_arrays(output(proxy))
C.check(not msgs.errors and list(got.keys()) == list(NAMES) and
        all(np.array_equal(got[n], zcyx[c]) for c, n in enumerate(NAMES)) and
        msgs.any_warning("two_series.ome.tif", "holds 2 images (series)", "only the first"),
        "two series: the first read whole, a warning names the file and the count (%s)"
        % [w.split("): ", 1)[-1].strip() for w in msgs.warnings])
simple.Delete(proxy)

# OpenDataFile picks the checked reader for OME-TIFF (not GDAL, not the OMETIFFReader).
for name in (path("tczyx.ome.tif"), path("zcyx.ome.tiff"), path("bioformats.ome.tif"),
             path("zcyx.tif")):
    proxy = simple.OpenDataFile(name)
    data = output(proxy)
    C.check(proxy.GetXMLName() == "CheckedTIFFReader" and data.GetNumberOfPoints() == X * Y * Z
            and data.GetPointData().GetNumberOfArrays() == 3,
            "OpenDataFile(%s) -> %s, %d points, %d arrays"
            % (os.path.basename(name), proxy.GetXMLName(), data.GetNumberOfPoints(),
               data.GetPointData().GetNumberOfArrays()))
    simple.Delete(proxy)


# The GUI's time: the time keeper takes the reader's TimestepValues.
proxy = simple.OpenDataFile(path("tzcyx.tif"))
proxy.UpdatePipelineInformation()
keeper = [float(t) for t in simple.GetTimeKeeper().TimestepValues]
C.check(keeper == [0.0, 0.5], "the time keeper shows the hyperstack's time steps %s" % keeper)
simple.Delete(proxy)


# ---- bad files ------------------------------------------------------------------------
def refused(label, name, words):
    proxy, msgs = open_checked(name)
    data = output(proxy)
    points = data.GetNumberOfPoints() if data is not None else 0
    named = msgs.any_error(os.path.basename(name), *words)
    C.check(named and points == 0,
            "%s: an error naming the file and %s; 0 points (%d); errors %s"
            % (label, words, points, [e.split("): ", 1)[-1].strip() for e in msgs.errors]))
    simple.Delete(proxy)


def imagej_like(name, pages, description):
    tifffile.imwrite(name, pages, photometric="minisblack", description=description,
                     metadata=None)


pages = np.ascontiguousarray(zcyx.transpose(1, 0, 2, 3)).reshape(-1, Y, X)  # Z*C pages
imagej_like(path("bad_images.tif"), pages,
            "ImageJ=1.11a\nimages=%d\nchannels=3\nslices=%d\nframes=2\nhyperstack=true\n"
            % (3 * Z, Z))
refused("ImageJ images != channels x slices x frames", path("bad_images.tif"),
        ["images=%d" % (3 * Z), "channels=3 x slices=%d x frames=2" % Z])
imagej_like(path("bad_missing.tif"), pages[:-5],
            "ImageJ=1.11a\nimages=%d\nchannels=3\nslices=%d\nhyperstack=true\n" % (3 * Z, Z))
refused("ImageJ missing pages", path("bad_missing.tif"),
        ["missing pages", "holds %d pages" % (3 * Z - 5)])
imagej_like(path("bad_unit.tif"), pages,
            "ImageJ=1.11a\nimages=%d\nchannels=3\nslices=%d\nhyperstack=true\nunit=furlong\n"
            % (3 * Z, Z))
refused("ImageJ unknown unit", path("bad_unit.tif"), ["unit=furlong", "does not know"])

planes_czt = [bf[t, c, z] for t in range(2) for z in range(Z) for c in range(3)]  # XYCZT
write_planes(path("bad_sizec.ome.tif"), planes_czt,
             bioformats_xml("XYCZT", 4, NAMES, '<TiffData/>'))
refused("OME SizeC=4 with 3 Channel elements", path("bad_sizec.ome.tif"),
        ["SizeC=4", "3 Channel elements"])
write_planes(path("bad_sizec_planes.ome.tif"), planes_czt,
             bioformats_xml("XYCZT", 4, [], '<TiffData/>'))
refused("OME SizeC=4 with the pages of 3 channels", path("bad_sizec_planes.ome.tif"),
        ["page %d of" % (3 * Z * 2 + 1), "holds %d pages" % (3 * Z * 2)])
write_planes(path("bad_ifd.ome.tif"), planes_czt,
             bioformats_xml("XYCZT", 3, NAMES,
                            '<TiffData IFD="0" PlaneCount="%d"/>'
                            '<TiffData FirstT="1" IFD="900" PlaneCount="%d"/>' % (3 * Z, 3 * Z)))
refused("OME TiffData beyond the pages", path("bad_ifd.ome.tif"),
        ["page 901", "holds %d pages" % (3 * Z * 2)])
write_planes(path("bad_unit.ome.tif"), planes_czt,
             bioformats_xml("XYCZT", 3, NAMES, '<TiffData/>', unit="furlong"))
refused("OME unknown unit", path("bad_unit.ome.tif"),
        ['PhysicalSizeZUnit="furlong"', "does not know"])
write_planes(path("bad_type.ome.tif"), [p.astype(np.float32) for p in planes_czt],
             bioformats_xml("XYCZT", 3, NAMES, '<TiffData/>'))
refused("OME Type uint16 over float32 pages", path("bad_type.ome.tif"),
        ["uint16 in its OME-XML", "pages hold float32"])
os.rename(os.path.join(folder, "set_t1.ome.tif"), os.path.join(folder, "moved.ome.tif"))
refused("OME file set with a file missing", os.path.join(folder, "set_t0.ome.tif"),
        ["set_t1.ome.tif", "cannot be opened"])

os.environ["MCV_MEMORY_LIMIT_MB"] = "4"
# One frame of the TZCYX file (not both): 91 x 109 x 91 x 3 float32 = 10.33 MiB, which
# the memory check rounds up.
refused("ImageJ TZCYX under a 4 MiB limit", path("tzcyx.tif"),
        ["needs 10.4 MiB for its %d voxels" % (3 * X * Y * Z), "only 4.0 MiB is available"])
del os.environ["MCV_MEMORY_LIMIT_MB"]

C.finish()
