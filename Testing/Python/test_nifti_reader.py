"""The NIfTI reader reads a file whole or refuses it (readers never
guess), on truncated and edited copies of the real Colin27 T1 (ch2.nii.gz) and on small
hand-written headers:

| input                                          | expected                           |
|------------------------------------------------|------------------------------------|
| ch2.nii.gz as shipped                          | 181 x 217 x 181, no error          |
| its first 5 kB (a cut gzip stream)             | error: not a complete gzip stream  |
| ch2 decompressed, cut to half (.nii)           | error: truncated, bytes promised   |
| the half .nii gzipped (a valid, short stream)  | error: truncated                   |
| header 200^3 float over 20^3 floats of data    | error: truncated                   |
| header 32767^3 float over 20^3 floats of data  | error: truncated (bytes promised)  |
| header with 7 dimensions                       | error: 7 dimensions                |
| header with spacing 0 / NaN                    | error: spacing                     |
| 20^3 header and data, written correctly        | 20 x 20 x 20, values as written    |
Each error names the file; the output then has no points (no zero-filled volume); the
process does not abort.
"""
import gzip
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

T.load_plugin(globals())
C = T.Checker("test_nifti_reader")
out = os.path.join(T.output_dir(), "nifti_reader")
os.makedirs(out, exist_ok=True)
original = T.data_file("ch2.nii.gz")


def header(dims, datatype=16, bitpix=32, spacing=(1.0, 1.0, 1.0)):
    """A NIfTI-1 single-file header (348 bytes + 4 bytes of extension flag)."""
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    dim = [len(dims)] + list(dims) + [1] * (7 - len(dims))
    struct.pack_into("<8h", h, 40, *dim)
    struct.pack_into("<hh", h, 70, datatype, bitpix)
    pixdim = [1.0] + list(spacing) + [1.0] * (7 - len(spacing))
    struct.pack_into("<8f", h, 76, *pixdim)
    struct.pack_into("<f", h, 108, 352.0)
    struct.pack_into("<f", h, 112, 1.0)  # scl_slope
    h[344:348] = b"n+1\0"
    return bytes(h)


def write(name, data):
    path = os.path.join(out, name)
    opener = gzip.open if name.endswith(".gz") else open
    with opener(path, "wb") as f:
        f.write(data)
    return path


raw = gzip.open(original, "rb").read()
with open(original, "rb") as f:
    compressed = f.read()
cube = [float(i % 7) for i in range(20 ** 3)]
cube_bytes = struct.pack("<%df" % len(cube), *cube)

cases = [
    ("first 5 kB of ch2.nii.gz", write("cut_stream.nii.gz.part", compressed[:5000]),
     ["not a complete gzip stream"]),
    ("ch2 cut to half (.nii)", write("half.nii", raw[:len(raw) // 2]), ["truncated", "promises"]),
    ("ch2 cut to half, gzipped", write("half.nii.gz", raw[:len(raw) // 2]), ["truncated"]),
    ("200^3 header over 20^3 data", write("big_header.nii", header((200, 200, 200)) + cube_bytes),
     ["truncated", "32000352"]),
    # Checked against the file before the memory: a truncated file, not a 128 TiB request
    # (the memory check has its rows in test_readers.py).
    ("32767^3 header", write("huge.nii", header((32767, 32767, 32767)) + cube_bytes),
     ["truncated", "140724603847004"]),
    ("7-D header", write("seven.nii", header((20, 20, 20, 1, 1, 1, 1)) + cube_bytes),
     ["7 dimensions"]),
    ("spacing 0", write("spacing0.nii", header((20, 20, 20), spacing=(1.0, 0.0, 1.0)) + cube_bytes),
     ["spacing 0"]),
    ("spacing NaN", write("spacingnan.nii",
                          header((20, 20, 20), spacing=(float("nan"), 1.0, 1.0)) + cube_bytes),
     ["spacing nan"]),
]
# The first case needs a .nii.gz name for the reader to take it as gzip.
os.replace(cases[0][1], cases[0][1][:-len(".part")])
cases[0] = (cases[0][0], cases[0][1][:-len(".part")], cases[0][2])


def read(path):
    reader = simple.NIfTIImageReader()
    msgs = T.Messages(reader)  # before the file name: the header is read when it is set
    reader.FileName = path
    reader.UpdatePipeline()
    info = reader.GetDataInformation()
    return reader, msgs, info.GetNumberOfPoints(), info.GetExtent()


reader, msgs, points, extent = read(original)
C.check(not msgs.errors and list(extent) == [0, 180, 0, 216, 0, 180],
        "ch2.nii.gz reads whole (%s, errors %s)" % (list(extent), msgs.errors))
simple.Delete(reader)

for label, path, words in cases:
    reader, msgs, points, _ = read(path)
    print("%s: %d points, errors %s" % (label, points, msgs.errors))
    named = msgs.any_error(os.path.basename(path), *words)
    C.check(named and points == 0,
            "%s: an error naming the file and %s, no output (%d points)" % (label, words, points))
    simple.Delete(reader)

good = write("cube.nii", header((20, 20, 20)) + cube_bytes)
reader, msgs, points, extent = read(good)
data = simple.servermanager.Fetch(reader)
values = data.GetPointData().GetScalars() if data else None
C.check(not msgs.errors and points == 8000 and values is not None and
        all(values.GetValue(i) == cube[i] for i in range(0, 8000, 97)),
        "a correct 20^3 file reads with its values (%d points, errors %s)" % (points, msgs.errors))
C.finish()
