"""A list of volume TIFF files (one OME-TIFF, ImageJ hyperstack or multi-page TIFF per time
point, as a time-lapse is often saved) read as a time series by the checked TIFF reader.

The files are written here with tifffile from the real brain (Colin27 T1 and AAL, every
second voxel: 91 x 109 x 91), step k of the series the brain + 100 k, so that a step read
from the wrong file shows. Checked:
- OpenDataFile of the list gives one reader with a time step per file (0, 1, 2), each step's
  channels bit for bit those written into its file, named and spaced as in the file; a
  time between steps reads the step at or before it; going back to step 0 after step 2
  reads file 0 again;
- the same for ImageJ hyperstacks and plain multi-page TIFF files (one array);
- a list of 2D one-page files stays a stack of slices (z), not a series;
- bad series, each an error naming the file and the problem, 0 points: a step on another
  grid, a step with other channels, a step holding several frames; a stack of 2D slices
  with a file of several pages (before: its first page taken as a slice, silently);
- the whole chain (DimensionReduction, FitTime "One time step") runs on the series and
  places every step with the fit of one step.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

import numpy as np  # noqa: E402
import tifffile  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_tiff_series")
OUT = T.fresh_output_dir("tiff_series")
NAMES = ("ch2", "aal")
SOURCE = np.stack(T.brain_arrays(NAMES, step=2)).astype(np.uint16)  # (C, Z, Y, X)
_, Z, Y, X = SOURCE.shape
STEPS = [SOURCE + 100 * k for k in range(3)]


def path(name):
    return os.path.join(OUT, name)


def write_ome(name, czyx, names=NAMES):
    tifffile.imwrite(path(name), czyx, ome=True, photometric="minisblack",
                     metadata={"axes": "CZYX", "Channel": {"Name": list(names)},
                               "PhysicalSizeX": 2.0, "PhysicalSizeY": 2.0,
                               "PhysicalSizeZ": 2.0})
    return path(name)


def opened(files):
    reader = simple.OpenDataFile(files)
    return reader, T.Messages(reader)


def read(reader, time):
    reader.UpdatePipeline(time)
    return reader.GetClientSideObject().GetOutputDataObject(0)


def check_series(label, files, expected, names):
    """expected[k]: the (C, Z, Y, X) values of step k."""
    reader, msgs = opened(files)
    reader.UpdatePipelineInformation()
    times = [float(t) for t in reader.TimestepValues]
    C.check(reader.GetXMLName() == "CheckedTIFFReader" and times == [0.0, 1.0, 2.0][:len(files)],
            "%s: the %d files are one series of %d steps on the checked TIFF reader (%s, %s)"
            % (label, len(files), len(files), reader.GetXMLName(), times))
    for k in list(range(len(files))) + [0]:  # and back to step 0: read again
        image = read(reader, float(k))
        got = T.volume_arrays(image)
        same = list(got.keys()) == list(names) and all(
            np.array_equal(got[n], expected[k][c]) for c, n in enumerate(names))
        C.check(not msgs.errors and same and image.GetDimensions() == (X, Y, Z) and
                image.GetInformation().Get(image.DATA_TIME_STEP()) == float(k),
                "%s: step %d holds file %d's channels %s bit for bit (got %s %s, errors %s)"
                % (label, k, k, list(names), list(got.keys()), image.GetDimensions(),
                   msgs.errors))
    got = T.volume_arrays(read(reader, 1.5))[names[0]]
    C.check(np.array_equal(got, expected[1][0]), "%s: time 1.5 reads step 1" % label)
    simple.Delete(reader)


def check_refused(label, files, *words):
    reader = simple.CheckedTIFFReader()
    msgs = T.Messages(reader)  # before the files: OpenDataFile reads the information at once
    reader.FileNames = files
    image = read(reader, 0.0)
    read(reader, 1.0)
    C.check(image.GetNumberOfPoints() == 0 and msgs.any_error(*words),
            "%s: refused, the error says %s (%s)"
            % (label, words, [e.split("): ", 1)[-1].strip() for e in msgs.errors]))
    simple.Delete(reader)


# ---- OME-TIFF: one file per time point --------------------------------------------------
ome = [write_ome("t%d.ome.tif" % k, STEPS[k]) for k in range(3)]
check_series("OME-TIFF series", ome, STEPS, NAMES)
image = read(opened(ome)[0], 2.0)
C.check(np.allclose(image.GetSpacing(), (2.0, 2.0, 2.0)) and
        T.field_strings(image, "LengthUnit") == ["µm"],
        "OME-TIFF series: the files' spacing and unit (%s %s)"
        % (image.GetSpacing(), T.field_strings(image, "LengthUnit")))

# ---- ImageJ hyperstacks (ZCYX) and plain multi-page TIFF files --------------------------
hyper = []
for k in range(2):
    hyper.append(path("h%d.tif" % k))
    tifffile.imwrite(hyper[-1], np.ascontiguousarray(STEPS[k].transpose(1, 0, 2, 3)),
                     imagej=True, metadata={"axes": "ZCYX", "spacing": 2.0, "unit": "um"})
check_series("ImageJ hyperstack series", hyper, STEPS, ("C1", "C2"))
plain = []
for k in range(2):
    plain.append(path("p%d.tif" % k))
    tifffile.imwrite(plain[-1], STEPS[k][0], photometric="minisblack")
check_series("plain multi-page TIFF series", plain, [s[:1] for s in STEPS], ("Tiff Scalars",))

# ---- 2D one-page files stay a stack of slices --------------------------------------------
slices = []
for z in range(3):
    slices.append(path("slice%d.tif" % z))
    tifffile.imwrite(slices[-1], SOURCE[0, 40 + z], photometric="minisblack")
reader, msgs = opened(slices)
reader.UpdatePipelineInformation()
image = read(reader, 0.0)
C.check(not msgs.errors and not reader.TimestepValues and image.GetDimensions() == (X, Y, 3) and
        np.array_equal(T.volume_arrays(image)["Tiff Scalars"], SOURCE[0, 40:43]),
        "three 2D files: a stack of 3 slices, no time steps (%s, %s)"
        % (image.GetDimensions(), list(reader.TimestepValues)))
simple.Delete(reader)

# ---- bad series --------------------------------------------------------------------------
other_grid = write_ome("grid.ome.tif", STEPS[1][:, :-1])
check_refused("a step on another grid", [ome[0], other_grid],
              "grid.ome.tif", "time step 2", "one grid")
other_channels = write_ome("names.ome.tif", STEPS[1], names=("T1", "AAL"))
check_refused("a step with other channels", [ome[0], other_channels],
              "names.ome.tif", "channels T1, AAL", "channels ch2, aal")
frames = path("frames.ome.tif")
tifffile.imwrite(frames, np.stack(STEPS[:2]), ome=True, photometric="minisblack",
                 metadata={"axes": "TCZYX", "Channel": {"Name": list(NAMES)}})
check_refused("a step of two frames", [ome[0], frames], "frames.ome.tif", "2 frames")
check_refused("a 2D stack with a volume in it", [slices[0], plain[0]],
              "p0.tif", "91 pages", "one page per file")

# ---- the chain on the series: one fit, every step placed with it -------------------------
reader, msgs = opened(ome)
features, reduction = mce.reduce_multichannel(reader, "PCA", "6D")
reduction.FitTime = "One time step"
reduction.FitTimeStep = 1
coordinates = []
for k in range(3):
    reduction.UpdatePipeline(float(k))
    out = reduction.GetClientSideObject().GetOutputDataObject(0)
    coordinates.append(vtk_to_numpy(out.GetPointData().GetArray("ReducedCoordinates")).copy())
C.check(not msgs.errors and all(c.shape == (X * Y * Z, 3) for c in coordinates) and
        not np.array_equal(coordinates[0], coordinates[2]),
        "the chain on the OME-TIFF series: 3 steps placed, step 0 and 2 differ (%s)"
        % [c.shape for c in coordinates])

C.finish()
