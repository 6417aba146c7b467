"""Bad OME-Zarr images: each gives one error that names the folder and the problem, an
empty output (0 points), and never an abort. Written with python3-zarr from a crop of the
real brain, then broken the way files break (a chunk file cut short or overwritten, a
.zarray removed or edited, metadata that is not an OME-Zarr image's, a type or codec the
reader does not read, a level that does not exist, a volume larger than the memory).
"""
import json
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

T.load_plugin({})
import numpy as np  # noqa: E402
import zarr  # noqa: E402
from numcodecs import BZ2, Delta  # noqa: E402

import omezarr_testing as Z  # noqa: E402

C = T.Checker("test_omezarr_bad_inputs")
OUT = T.fresh_output_dir("omezarr_bad_inputs")

brain = Z.brain_arrays()
small = np.ascontiguousarray(brain[:, 80:120, 60:124, 40:104])  # 3 x 40 x 64 x 64
SCALES = [[1, 1, 1, 1], [1, 2, 2, 2]]
CHUNKS = (1, 20, 32, 32)


def image(name, **options):
    """A good 2-level image to break."""
    levels = [small, small[:, ::2, ::2, ::2]]
    return Z.write_image(os.path.join(OUT, name + ".ome.zarr"), levels,
                         scales=options.pop("scales", SCALES), chunks=CHUNKS, **options)


def edit_json(path, change):
    with open(path) as f:
        value = json.load(f)
    change(value)
    with open(path, "w") as f:
        json.dump(value, f)


def refused(folder, what, *words, level=None):
    """Opens `folder` with the OME-Zarr reader (named, as OpenDataFile may not pick it for a
    broken folder) and checks one error with `words` and the folder, and 0 points."""
    reader = simple.OMEZarrReader()  # observed before it reads the folder's metadata
    msgs = T.Messages(reader)
    if level is not None:
        reader.ResolutionLevel = level
    reader.FileName = folder
    reader.UpdatePipeline()
    points = reader.GetDataInformation().GetNumberOfPoints()
    hit = [e for e in msgs.errors if folder in e and all(w.lower() in e.lower() for w in words)]
    shown = [line for e in (hit or msgs.errors or ["(no error)"]) for line in e.splitlines()
             if "OME-Zarr folder" in line or e.startswith("(no")][:1] or ["?"]
    C.check(bool(hit) and points == 0, "%s: error naming the folder and %s, %d points: %s"
            % (what, words, points, shown[0].replace(OUT + "/", "")))
    simple.Delete(reader)


# The good image first: the breaks below are what makes each fail.
good = image("good")
reader = simple.OpenDataFile(good)
reader.UpdatePipeline()
C.check(reader.GetDataInformation().GetNumberOfPoints() == 40 * 64 * 64,
        "the unbroken image reads (%d points)" % reader.GetDataInformation().GetNumberOfPoints())

# A missing .zarray of the level read.
folder = image("no_zarray")
os.remove(os.path.join(folder, "0", ".zarray"))
refused(folder, "missing .zarray", "has no .zarray for resolution level 0")

# A chunk of the wrong size: an uncompressed chunk cut short; a blosc chunk replaced by
# one of another array's (valid Blosc, wrong size); a zlib chunk overwritten with garbage.
folder = image("short_chunk", compressor="none")
chunk = os.path.join(folder, "0", "2.1.0.1")
with open(chunk, "r+b") as f:
    f.truncate(1000)
refused(folder, "uncompressed chunk cut short", "chunk '2.1.0.1'", "holds 1000 bytes instead of the 20480")
folder = image("wrong_size_chunk")
other = zarr.open(os.path.join(OUT, "other.zarr"), mode="w", shape=(10, 10), chunks=(10, 10),
                  dtype="u1")
other[:] = 1
shutil.copy(os.path.join(OUT, "other.zarr", "0.0"), os.path.join(folder, "0", "0.0.1.1"))
refused(folder, "blosc chunk of another size", "chunk '0.0.1.1'", "decompresses to 100 bytes instead of the 20480")
folder = image("corrupt_chunk", compressor="zlib")
with open(os.path.join(folder, "0", "1.0.0.0"), "r+b") as f:
    f.seek(2)
    f.write(b"\xff" * 64)
refused(folder, "corrupt zlib chunk", "chunk '1.0.0.0'", "not a valid zlib stream")
folder = image("corrupt_blosc")
with open(os.path.join(folder, "0", "0.1.1.0"), "wb") as f:
    f.write(b"not a blosc buffer at all")
refused(folder, "garbage blosc chunk", "chunk '0.1.1.0'", "not a valid Blosc buffer")

# Types and codecs that are not read.
folder = image("complex", dtype="<c8")
refused(folder, "complex dtype", "dtype '<c8' (complex numbers)")
folder = image("bool", dtype="|b1")
refused(folder, "bool dtype", "dtype '|b1' (booleans)")
folder = image("bz2")
for level in ("0", "1"):
    edit_json(os.path.join(folder, level, ".zarray"),
              lambda z: z.update(compressor=BZ2(level=5).get_config()))
refused(folder, "bz2 compressor", "compressed with 'bz2'")
folder = image("filters")
edit_json(os.path.join(folder, "0", ".zarray"),
          lambda z: z.update(filters=[Delta(dtype="u1").get_config()]))
refused(folder, "a filter", "filters (delta)")

# A shape that disagrees with the axes; a level that does not exist.
folder = image("wrong_shape")
edit_json(os.path.join(folder, "0", ".zarray"),
          lambda z: z.update(shape=[40, 64, 64], chunks=[20, 32, 32]))
refused(folder, "3-D shape for 4 axes", "shape [40, 64, 64] (3 dimensions) for the 4 axes c, z, y, x")
refused(good, "ResolutionLevel 2 of 2 levels", "has no resolution level 2", level=2)

# Not an OME-Zarr image.
folder = image("no_zattrs")
os.remove(os.path.join(folder, ".zattrs"))
refused(folder, "missing .zattrs", "has no .zattrs")
folder = image("no_multiscales")
edit_json(os.path.join(folder, ".zattrs"), lambda a: a.pop("multiscales"))
refused(folder, ".zattrs without multiscales", "has no multiscales")
folder = image("axes_order")
edit_json(os.path.join(folder, ".zattrs"), lambda a: a["multiscales"][0].update(
    axes=[{"name": n} for n in ("c", "x", "y", "z")]))
refused(folder, "axes c, x, y, z", "axes (c, x, y, z)", "not a subset of t, c, z, y, x")

# A shape that does not fit in memory: 3 x 100000^3 uint16 (only the metadata is written).
folder = os.path.join(OUT, "huge.ome.zarr")
root = zarr.group(store=zarr.DirectoryStore(folder), overwrite=True)
root.create_dataset("0", shape=(3, 100000, 100000, 100000), chunks=(1, 256, 256, 256),
                    dtype="<u2")
root.attrs["multiscales"] = [{"version": "0.4", "axes": [{"name": n} for n in "czyx"],
                              "datasets": [{"path": "0", "coordinateTransformations": [
                                  {"type": "scale", "scale": [1, 1, 1, 1]}]}]}]
refused(folder, "3 x 100000^3 voxels, default level", "no resolution level that fits in memory")
refused(folder, "3 x 100000^3 voxels, level 0", "cannot hold the extent", "needs", level=0)

C.finish()
