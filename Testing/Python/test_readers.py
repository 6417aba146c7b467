"""The MetaImage and TIFF readers read a file whole or refuse it (readers
never guess), on copies of the real volumes (Colin27 T1 ch2.nii.gz, brainsmall.den)
written here with VTK's writers, cut, edited or replaced by random bytes; the NIfTI rows
of the memory check are here too (the other NIfTI rows: test_nifti_reader.py).

"ParaView" is what ParaView 5.11's own reader does with the input (measured in pvbatch:
MetaImageReader = vtkMetaImageReader, TIFFSeriesReader = vtkTIFFReader; OpenDataFile
gives a .tif to GDALRasterReader, which reads its first page only, as 2D cell data).
"Now" is what this test checks, with the plugin's CheckedMetaImageReader
(vtkCheckedMetaImageReader) and CheckedTIFFReader (vtkCheckedTIFFReader). Every refusal is
one error naming the file and the problem, and an output of 0 points.

| format    | input                                     | ParaView                          | now                                  |
|-----------|-------------------------------------------|-----------------------------------|--------------------------------------|
| .mhd/.raw | ch2 written by vtkMetaImageWriter          | read                              | read, same voxels as ch2.nii.gz      |
| .mhd/.zraw| the same, compressed                      | read                              | read, same voxels                    |
| .mha      | the same, header and data in one file     | read                              | read, same voxels                    |
| .mhd      | a %03d pattern of 181 slice files         | read                              | read, same voxels                    |
| .mhd      | .raw cut to half                          | full volume, 2nd half 0, no error | error: truncated, bytes promised/held|
| .mhd      | .raw one byte short                       | full volume, no error             | error: truncated                     |
| .mha      | cut to half                               | full volume, 2nd half 0, no error | error: truncated                     |
| .mhd      | .zraw cut to half                         | partly zero volume, no error      | error: not a complete zlib stream    |
| .mhd      | .raw missing                              | zero-filled volume + an error     | error: names the missing .raw        |
| .mhd      | one slice file of the pattern missing     | volume with a hole, stderr only   | error: names the missing slice file  |
| .mhd      | DimSize 181 0 181                         | 0 points, no error                | error: dimension 2 = 0               |
| .mhd      | DimSize 181 -217 181                      | abort (std::bad_alloc)            | error: dimension 2 = -217            |
| .mhd      | DimSize 32767^3 over ch2's .raw           | abort (Unable to allocate 32 TiB) | error: truncated (bytes promised)    |
| .mhd      | DimSize 181 217 200 over ch2's .raw       | 200 slices, 19 not in the file    | error: truncated                     |
| .mhd      | 4096 x 4096 x 2048 over a sparse 32 GiB   | abort (Unable to allocate)*       | error: needs 32 GiB (1 GiB limit)    |
| .mhd      | ElementSpacing 1 0 1                      | read with spacing 0, no error     | error: spacing 0                     |
| .mhd      | ElementSpacing nan 1 1                    | 1 voxel + "cannot parse"          | error: spacing nan                   |
| .mhd      | ElementType MET_FOO                       | 1 voxel + "Unknown data type"     | error: ElementType MET_FOO           |
| .mhd      | NDims 7                                   | 1 voxel + "cannot parse"          | error: NDims                         |
| .mhd      | random bytes (explicit reader)            | (OpenDataFile: no reader)         | error: no MetaImage header           |
| .mhd .mha | random bytes, OpenDataFile                | "No reader found for '<file>'"    | the same (ParaView's row, no code)   |
| .tif      | ch2 as 181 pages, uncompressed / PackBits | read                              | read, same voxels as ch2.nii.gz      |
| .tif      | 20 Deflate pages written here             | read                              | read, same voxels                    |
| .tif      | brainsmall as a stack of 84 2D files      | read                              | read, same voxels as TIFFSeriesReader|
| .tif      | cut to half (uncompressed; PackBits)      | 90 (71) pages, no error           | error: truncated, directory of page 91 (72) |
| .tif      | writer stopped after page 90 (chain ends) | 90 pages, no error                | error: truncated, pages numbered 181 |
| .tif      | a page whose strip ends beyond the file   | garbage + "Problem reading slice" | error: truncated, data of page 1 ends|
| .tif      | one Deflate strip corrupted (bad checksum)| wrong slice, no error             | error: Deflate strip not complete    |
| .tif      | an LZW strip of random bytes              | zero slice + "Problem reading"    | error: could not be read whole (libtiff's reason) |
| .tif      | BigTIFF 60000 x 60000 x 8, sparse 27 GiB  | abort (Unable to allocate)*       | error: needs 26.9 GiB (1 GiB limit) |
| .tif      | 3 bits per sample                         | garbage + "Problem reading RGB"   | error: 3 bits per sample             |
| .tif      | width 0 / SampleFormat 9 (explicit reader)| 0 points + "Unable to open file"  | error: a page of 0 x 20 pixels / sample format 9 |
| .tif      | first 5 kB / random bytes (explicit)      | 0 points + "Unable to open file"  | error: truncated / not a TIFF file   |
| .tif      | random bytes, OpenDataFile                | "No reader found for '<file>'"    | the same (ParaView's row, no code)   |
| .tif      | first 5 kB, OpenDataFile                  | "No reader found for '<file>'"    | the checked reader: truncated, 0 points |
| .den      | cut to half, OpenDataFile                 | (plugin reader) "No reader found" | VolPackDenReader: truncated, 0 points|
| .tif      | resolution 0 or 0/0 (NaN), unit cm        | spacing 1 (no usable resolution)  | the same (ParaView's row, no code)   |
| .tif      | CustomDataSpacing 1 1 0                   | spacing 0                         | error: spacing 0 (CustomDataSpacing) |
| stack     | one slice cut to half                     | black slice, no error             | error: names the slice, truncated    |
| stack     | one slice of random bytes                 | black slice, no error             | error: names the slice, not a TIFF   |
| stack     | one slice 100 x 100 among 128 x 128       | volume + "Problem reading slice"  | error: names the slice, sizes differ |
| any       | a good file, then a cut one, same reader  | -                                 | 0 points (no stale volume)           |
| .mhd .tif .nii.gz | ch2 under a 1 MiB memory limit    | (allocates)                       | error: needs 6.8 MiB, 1.0 MiB available |
| OpenDataFile | .mhd, .mha, .tif, .tiff, a stack list  | MetaImageReader, GDALRasterReader | CheckedMetaImageReader, CheckedTIFFReader |
* measured under ulimit -v 8 GB; without a limit the process takes what it can get.
Not detectable from the file: a PackBits strip overwritten with other bytes of the same
structure (PackBits has no checksum); such a file reads as it decodes.
"""
import gzip
import os
import random
import shutil
import struct
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from vtkmodules.vtkImagingCore import vtkExtractVOI  # noqa: E402
from vtkmodules.vtkIOImage import vtkMetaImageWriter, vtkTIFFWriter  # noqa: E402

T.load_plugin(globals())
C = T.Checker("test_readers")
out = os.path.join(T.output_dir(), "readers")
shutil.rmtree(out, ignore_errors=True)
os.makedirs(os.path.join(out, "pattern"))
ch2_path = T.data_file("ch2.nii.gz")
den_path = T.data_file("brainsmall.den")
random.seed(19)


def path(name):
    return os.path.join(out, name)


def write(name, data):
    with open(path(name), "wb") as f:
        f.write(data)
    return path(name)


def content(name):
    with open(path(name), "rb") as f:
        return f.read()


def voxels(image):
    return bytes(memoryview(image.GetPointData().GetScalars()))


def source_image(proxy):
    proxy.UpdatePipeline()
    return proxy.GetClientSideObject().GetOutputDataObject(0)


ch2 = source_image(NIfTIImageReader(FileName=ch2_path))  # noqa: F821 (load_plugin)
den = source_image(VolPackDenReader(FileName=den_path))  # noqa: F821
W, H, D = ch2.GetDimensions()
ch2_voxels = voxels(ch2)

# ---- MetaImage copies of ch2 ------------------------------------------------------------
for name, compress in (("ch2.mhd", False), ("ch2z.mhd", True), ("ch2.mha", False)):
    writer = vtkMetaImageWriter()
    writer.SetInputData(ch2)
    writer.SetFileName(path(name))
    if name.endswith(".mhd"):
        writer.SetRAWFileName(path(name[:-4] + (".zraw" if compress else ".raw")))
    writer.SetCompression(compress)
    writer.Write()
header = content("ch2.mhd").decode()
raw = content("ch2.raw")


def mhd(name, replace=(), data=None, datafile=None):
    """A copy of ch2.mhd with fields replaced, over `data` (default: ch2's .raw itself)."""
    text = header
    for old, new in replace:
        assert old in text, old
        text = text.replace(old, new)
    text = text.replace("ElementDataFile = ch2.raw",
                        "ElementDataFile = " + (datafile or ("ch2.raw" if data is None
                                                             else name + ".raw")))
    if data is not None:
        write(name + ".raw", data)
    return write(name + ".mhd", text.encode())


for k in range(D):  # a %03d pattern of slice files
    with open(os.path.join(out, "pattern", "s%03d.raw" % k), "wb") as f:
        f.write(ch2_voxels[k * W * H:(k + 1) * W * H])
with open(os.path.join(out, "pattern", "ch2.mhd"), "w") as f:
    f.write(header.replace("ElementDataFile = ch2.raw", "ElementDataFile = s%03d.raw 0 180 1"))
shutil.copytree(os.path.join(out, "pattern"), os.path.join(out, "pattern_hole"))
os.remove(os.path.join(out, "pattern_hole", "s090.raw"))
sparse = mhd("sparse", [("DimSize = 181 217 181", "DimSize = 4096 4096 2048")], b"")
os.truncate(path("sparse.raw"), 4096 * 4096 * 2048)  # 32 GiB, no disk blocks
mha = content("ch2.mha")
zraw = content("ch2z.zraw")
write("half_z.zraw", zraw[:len(zraw) // 2])

# ---- TIFF copies: ch2 as multi-page files, brainsmall as a stack of 2D files -------------
for name, packbits in (("ch2.tif", False), ("ch2_packbits.tif", True)):
    writer = vtkTIFFWriter()
    writer.SetInputData(ch2)
    if not packbits:
        writer.SetCompressionToNoCompression()  # the default is PackBits
    writer.SetFileName(path(name))
    writer.Write()
ext = den.GetExtent()
stack_files = T.write_tiff_stack(den, path("stack"))
for stack in ("stack_cut", "stack_random", "stack_size"):
    shutil.copytree(path("stack"), path(stack))
slice_bytes = content("stack/slice_042.tif")
write("stack_cut/slice_042.tif", slice_bytes[:len(slice_bytes) // 2])
write("stack_random/slice_042.tif", bytes(random.getrandbits(8) for _ in slice_bytes))
voi = vtkExtractVOI()
voi.SetInputData(den)
voi.SetVOI(0, 99, 0, 99, 42, 42)
writer = vtkTIFFWriter()
writer.SetInputConnection(voi.GetOutputPort())
writer.SetFileName(path("stack_size/slice_042.tif"))
writer.Write()


def stack_of(folder):
    return [path("%s/slice_%03d.tif" % (folder, k)) for k in range(ext[4], ext[5] + 1)]


def tiff(width, height, pages, compression=1, bits=8, sample_format=1, resolution=None,
         declared=None, sparse=False, big=False):
    """A little-endian TIFF written here (BigTIFF with `big`): one strip per page (zlib for
    compression 8), PageNumber tags, optionally a resolution (pixels per cm). `declared`:
    the strip byte count written in the tags instead of the true one; `sparse`: the strips
    lie in a sparse tail of the file (os.truncate it), not written."""
    offset, count_of = ("Q", "Q") if big else ("I", "H")
    entry = 20 if big else 12
    out = bytearray(b"II+\x00\x08\x00\x00\x00" + bytes(8) if big else b"II*\x00" + bytes(4))
    link = 8 if big else 4
    for k, page in enumerate(pages):
        data = zlib.compress(page) if compression == 8 else page
        count = declared or len(data)
        if sparse:
            strip = (1 << 20) + k * count
        else:
            strip = len(out)
            out += data + b"\0" * (len(data) % 2)
        long_ = 16 if big else 4  # LONG8 in a BigTIFF
        tags = [(256, 4, width), (257, 4, height), (258, 3, bits), (259, 3, compression),
                (262, 3, 1), (273, long_, strip), (277, 3, 1), (278, 4, height),
                (279, long_, count), (297, 3, (k, len(pages))), (339, 3, sample_format)]
        ifd = len(out)
        head = 8 if big else 2
        rational = ifd + head + entry * (len(tags) + 3) + (8 if big else 4)  # after it
        if resolution is not None:
            tags += [(282, 5, rational), (283, 5, rational), (296, 3, 3)]  # unit: cm
        struct.pack_into("<" + offset, out, link, ifd)
        out += struct.pack("<" + count_of, len(tags))
        for tag, kind, value in sorted(tags):
            values = value if isinstance(value, tuple) else (value,)
            packed = struct.pack("<%d%s" % (len(values), {3: "H", 4: "I", 5: offset, 16: "Q"}[kind]),
                                 *values)
            out += struct.pack("<HH" + offset, tag, kind, len(values))
            out += packed + bytes((8 if big else 4) - len(packed))
        link = len(out)
        out += bytes(8 if big else 4)
        if resolution is not None:
            out += struct.pack("<II", *resolution)
    return bytes(out)


def cut_after_page(data, pages):
    """A multi-page TIFF as a writer leaves it when it stops after `pages` pages: the
    directory chain ends there (libtiff links the next directory only once it is written).
    The file ends after that directory and the values it points to."""
    data = bytearray(data)
    ifd = struct.unpack_from("<I", data, 4)[0]
    for _ in range(pages - 1):
        n = struct.unpack_from("<H", data, ifd)[0]
        ifd = struct.unpack_from("<I", data, ifd + 2 + 12 * n)[0]
    n = struct.unpack_from("<H", data, ifd)[0]
    link = ifd + 2 + 12 * n
    end = link + 4
    for i in range(n):
        _, kind, count, value = struct.unpack_from("<HHII", data, ifd + 2 + 12 * i)
        size = count * {1: 1, 2: 1, 3: 2, 4: 4, 5: 8}.get(kind, 1)
        if size > 4:
            end = max(end, value + size)
    struct.pack_into("<I", data, link, 0)
    return bytes(data[:end])


slices = [ch2_voxels[k * W * H:(k + 1) * W * H] for k in range(60, 120, 3)]
write("deflate.tif", tiff(W, H, slices, compression=8))
corrupt = bytearray(content("deflate.tif"))
for i in range(len(corrupt) // 2, len(corrupt) // 2 + 50):
    corrupt[i] ^= 0x5a
write("deflate_corrupt.tif", bytes(corrupt))
tif = content("ch2.tif")
packbits = content("ch2_packbits.tif")
write("huge.tif", tiff(60000, 60000, [b""] * 8, declared=60000 * 60000, sparse=True, big=True))
os.truncate(path("huge.tif"), (1 << 20) + 8 * 60000 * 60000)  # 27 GiB, no disk blocks
write("bigtiff.tif", tiff(W, H, slices, big=True))
gradient = bytes(range(200)) * 2

# ---- the rows ---------------------------------------------------------------------------
# (format, label, reader, files, words the error must hold besides the file's name)
# reader "mhd": CheckedMetaImageReader; "tif": CheckedTIFFReader; "nii": NIfTIImageReader.
ROWS = [
    (".mhd", ".raw cut to half", "mhd", mhd("half", data=raw[:len(raw) // 2]),
     ["truncated", "promises 7109137 bytes", "holds 3554568"]),
    (".mhd", ".raw one byte short", "mhd", mhd("short", data=raw[:-1]),
     ["truncated", "holds 7109136"]),
    (".mha", "cut to half", "mhd", write("half.mha", mha[:len(mha) // 2]),
     ["truncated", "the file holds"]),
    (".mhd", ".zraw cut to half", "mhd",
     write("half_z.mhd", content("ch2z.mhd").replace(b"ch2z.zraw", b"half_z.zraw")),
     ["half_z.zraw", "not a complete zlib stream"]),
    (".mhd", ".raw missing", "mhd", mhd("missing", datafile="missing.raw"),
     ["missing.raw", "cannot be opened"]),
    (".mhd", "a slice file of the pattern missing", "mhd",
     os.path.join(out, "pattern_hole", "ch2.mhd"), ["s090.raw", "cannot be opened"]),
    (".mhd", "DimSize 181 0 181", "mhd",
     mhd("dim0", [("DimSize = 181 217 181", "DimSize = 181 0 181")]), ["dimension 2 = 0"]),
    (".mhd", "DimSize 181 -217 181", "mhd",
     mhd("dimneg", [("DimSize = 181 217 181", "DimSize = 181 -217 181")]),
     ["dimension 2 = -217"]),
    (".mhd", "DimSize 32767^3", "mhd",
     mhd("huge", [("DimSize = 181 217 181", "DimSize = 32767 32767 32767")]),
     ["truncated", "promises 35181150961663 bytes"]),
    (".mhd", "DimSize 181 217 200", "mhd",
     mhd("bigger", [("DimSize = 181 217 181", "DimSize = 181 217 200")]),
     ["truncated", "promises 7855400 bytes"]),
    (".mhd", "ElementSpacing 1 0 1", "mhd",
     mhd("spacing0", [("ElementSpacing = 1 1 1", "ElementSpacing = 1 0 1")]),
     ["spacing 0 along axis 2"]),
    (".mhd", "ElementSpacing nan 1 1", "mhd",
     mhd("spacingnan", [("ElementSpacing = 1 1 1", "ElementSpacing = nan 1 1")]),
     ["spacing nan along axis 1"]),
    (".mhd", "ElementType MET_FOO", "mhd", mhd("type", [("MET_UCHAR", "MET_FOO")]),
     ["ElementType", "MET_FOO"]),
    (".mhd", "NDims 7", "mhd", mhd("ndims7", [("NDims = 3", "NDims = 7")]), ["NDims", "7"]),
    (".mhd", "random bytes", "mhd",
     write("random.mhd", bytes(random.getrandbits(8) for _ in range(100000))),
     ["no MetaImage header"]),
    (".tif", "cut to half, uncompressed", "tif", write("half.tif", tif[:len(tif) // 2]),
     ["truncated", "directory of page 91"]),
    (".tif", "cut to half, PackBits", "tif",
     write("half_packbits.tif", packbits[:len(packbits) // 2]),
     ["truncated", "directory of page 72"]),
    (".tif", "writer stopped after page 90", "tif",
     write("stopped.tif", cut_after_page(tif, 90)),
     ["truncated", "numbered as 181", "holds 90"]),
    (".tif", "a strip ending beyond the file", "tif",
     write("short_strip.tif", tiff(200, 200, [gradient], declared=40000)),
     ["truncated", "image data of page 1 ends at byte"]),
    (".tif", "one Deflate strip corrupted", "tif", path("deflate_corrupt.tif"),
     ["Deflate strip on page 10", "not a complete zlib stream", "incorrect data check"]),
    (".tif", "an LZW strip of random bytes", "tif",
     write("lzw_random.tif", tiff(W, H, [bytes(random.getrandbits(8) for _ in range(20000))],
                                  compression=5)),
     ["could not be read whole", "libtiff", "Using code not yet in table"]),
    (".tif", "3 bits per sample", "tif", write("bits3.tif", tiff(20, 20, [gradient], bits=3)),
     ["3 bits per sample"]),
    (".tif", "width 0", "tif", write("width0.tif", tiff(0, 20, [gradient])),
     ["0 x 20 pixels"]),
    (".tif", "SampleFormat 9", "tif",
     write("format9.tif", tiff(20, 20, [gradient], sample_format=9)), ["sample format 9"]),
    (".tif", "its first 5 kB", "tif", write("head.tif", tif[:5000]),
     ["truncated", "directory of page 1"]),
    (".tif", "random bytes", "tif",
     write("random.tif", bytes(random.getrandbits(8) for _ in range(100000))),
     ["not a TIFF file"]),
    ("stack", "one slice cut to half", "tif", stack_of("stack_cut"),
     ["stack of 84 files", "number 43", "truncated"]),
    ("stack", "one slice of random bytes", "tif", stack_of("stack_random"),
     ["stack of 84 files", "number 43", "not a TIFF file"]),
    ("stack", "one slice of 100 x 100", "tif", stack_of("stack_size"),
     ["stack of 84 files", "100 x 100 pixels", "128 x 128"]),
]


def read(reader, files, **properties):
    """A reader of the plugin on `files`; its messages are caught from the start (the
    header is read when the file name is set). Returns (proxy, messages, output)."""
    if reader == "mhd":
        proxy = simple.CheckedMetaImageReader()
    elif reader == "tif":
        proxy = simple.CheckedTIFFReader()
    else:
        proxy = NIfTIImageReader()  # noqa: F821
    msgs = T.Messages(proxy)
    for key, value in properties.items():
        setattr(proxy, key, value)
    if reader == "tif":
        proxy.FileNames = files if isinstance(files, list) else [files]
    else:
        proxy.FileName = files
    proxy.UpdatePipeline()
    return proxy, msgs, proxy.GetClientSideObject().GetOutputDataObject(0)


def points(data):
    return data.GetNumberOfPoints() if data is not None else 0


def refused(label, reader, files, words, **properties):
    proxy, msgs, data = read(reader, files, **properties)
    name = files[0] if isinstance(files, list) else files
    # In a stack, the error names the slice at fault (words), not the first file.
    named = msgs.any_error(*words) and (isinstance(files, list) or
                                        msgs.any_error(os.path.basename(name)))
    C.check(named and points(data) == 0 and len(msgs.errors) >= 1,
            "%s: an error naming the file and %s; 0 points (%d); errors %s"
            % (label, words, points(data), [e.split("): ", 1)[-1].strip() for e in msgs.errors]))
    simple.Delete(proxy)


def read_whole(label, reader, files, expected, spacing=(1.0, 1.0, 1.0)):
    proxy, msgs, data = read(reader, files)
    same = data is not None and points(data) > 0 and voxels(data) == expected
    C.check(not msgs.errors and same and tuple(data.GetSpacing()) == tuple(spacing),
            "%s: read whole, the voxels of the source (%d points, spacing %s, errors %s)"
            % (label, points(data), data and data.GetSpacing(), msgs.errors))
    simple.Delete(proxy)


# Good files: the voxels of the volume they were written from.
read_whole(".mhd/.raw", "mhd", path("ch2.mhd"), ch2_voxels)
read_whole(".mhd/.zraw (compressed)", "mhd", path("ch2z.mhd"), ch2_voxels)
read_whole(".mha", "mhd", path("ch2.mha"), ch2_voxels)
read_whole(".mhd, %03d pattern of 181 files", "mhd", os.path.join(out, "pattern", "ch2.mhd"),
           ch2_voxels)
read_whole(".tif, 181 pages uncompressed", "tif", path("ch2.tif"), ch2_voxels)
read_whole(".tif, 181 pages PackBits", "tif", path("ch2_packbits.tif"), ch2_voxels)
read_whole(".tif, 20 Deflate pages", "tif", path("deflate.tif"), b"".join(slices))
read_whole(".tif, 20 BigTIFF pages", "tif", path("bigtiff.tif"), b"".join(slices))
# The stack as ParaView's own TIFF Series Reader reads it (the same slices, the same rows).
series = simple.TIFFSeriesReader(FileNames=stack_files)
series.ReadAsImageStack = 1
read_whole("stack of 84 2D .tif files", "tif", stack_files, voxels(source_image(series)))
simple.Delete(series)

for fmt, label, reader, files, words in ROWS:
    refused("%s %s" % (fmt, label), reader, files, words)

# TIFF spacing: a resolution of 0 or 0/0 is no resolution (VTK uses it only when positive:
# spacing 1, as for the many TIFF files without one); a custom spacing of 0 is refused.
for name, resolution in (("resolution0.tif", (0, 1)), ("resolution_nan.tif", (0, 0)),
                         ("resolution4.tif", (4, 1))):
    proxy, msgs, data = read("tif", write(name, tiff(20, 20, [gradient], resolution=resolution)))
    expected = 2.5 if resolution == (4, 1) else 1.0  # 4 pixels per cm: 2.5 mm
    C.check(not msgs.errors and points(data) == 400 and data.GetSpacing()[0] == expected,
            "%s: read, spacing %s (expected %g; ParaView's own behaviour)"
            % (name, data and data.GetSpacing(), expected))
    simple.Delete(proxy)
refused(".tif CustomDataSpacing 1 1 0", "tif", path("resolution4.tif"),
        ["spacing 0 along axis 3", "CustomDataSpacing"], UseCustomDataSpacing=1,
        CustomDataSpacing=[1.0, 1.0, 0.0])

# No stale volume: a good file, then a cut one, in the same reader.
for reader, good, bad in (("mhd", path("ch2.mhd"), path("half.mhd")),
                          ("tif", path("ch2.tif"), path("half.tif"))):
    proxy, msgs, data = read(reader, good)
    first = points(data)
    if reader == "tif":
        proxy.FileNames = [bad]
    else:
        proxy.FileName = bad
    proxy.UpdatePipeline()
    data = proxy.GetClientSideObject().GetOutputDataObject(0)
    C.check(first == W * H * D and points(data) == 0 and msgs.any_error("truncated"),
            "%s: a good file (%d points), then a cut one in the same reader: 0 points (%d)"
            % (reader, first, points(data)))
    simple.Delete(proxy)

# Memory: MCV_MEMORY_LIMIT_MB stands in for a small machine (MemoryBudget).
os.environ["MCV_MEMORY_LIMIT_MB"] = "1024"
refused(".mhd 4096 x 4096 x 2048 over a sparse 32 GiB .raw", "mhd", sparse,
        ["needs 32.0 GiB", "only 1.0 GiB is available"])
refused(".tif 60000 x 60000 x 8 pages, sparse", "tif", path("huge.tif"),
        ["needs 26.9 GiB", "only 1.0 GiB is available"])
os.environ["MCV_MEMORY_LIMIT_MB"] = "1"
for reader, name in (("mhd", path("ch2.mhd")), ("tif", path("ch2.tif")), ("nii", ch2_path)):
    refused("%s under a 1 MiB limit" % os.path.basename(name), reader, name,
            ["needs 6.8 MiB for its 7109137 voxels", "only 1.0 MiB is available"])
del os.environ["MCV_MEMORY_LIMIT_MB"]

# OpenDataFile (and File > Open) picks the plugin's readers: ParaView 5.11's reader factory
# tries its readers in the order of their proxy names.
for files, expected in ((path("ch2.mhd"), "CheckedMetaImageReader"),
                        (path("ch2.mha"), "CheckedMetaImageReader"),
                        (path("ch2.tif"), "CheckedTIFFReader"),
                        (stack_files, "CheckedTIFFReader")):
    proxy = simple.OpenDataFile(files)
    proxy.UpdatePipeline()
    got = proxy.GetXMLName()
    C.check(got == expected and points(proxy.GetClientSideObject().GetOutputDataObject(0)) > 0,
            "OpenDataFile(%s) -> %s" % (os.path.basename(files if isinstance(files, str)
                                                         else files[0]), got))
    simple.Delete(proxy)
shutil.copy(path("ch2.tif"), path("ch2_copy.tiff"))
proxy = simple.OpenDataFile(path("ch2_copy.tiff"))
C.check(proxy.GetXMLName() == "CheckedTIFFReader", "OpenDataFile(.tiff) -> %s"
        % proxy.GetXMLName())
simple.Delete(proxy)
# Cut files through OpenDataFile: the plugin's readers take them (a TIFF or .den whose
# header libtiff or the .den check cannot get past too, so that the error says why), and
# refuse them.
with open(den_path, "rb") as f:
    den_bytes = f.read()
write("half.den", den_bytes[:len(den_bytes) // 2])
for name, expected in (("half.mhd", "CheckedMetaImageReader"), ("half.tif", "CheckedTIFFReader"),
                       ("head.tif", "CheckedTIFFReader"), ("half.den", "VolPackDenReader")):
    proxy = simple.OpenDataFile(path(name))
    proxy.UpdatePipeline()
    C.check(proxy.GetXMLName() == expected and
            points(proxy.GetClientSideObject().GetOutputDataObject(0)) == 0,
            "OpenDataFile(%s): %s (%s), 0 points" % (name, expected, proxy.GetXMLName()))
    simple.Delete(proxy)
# ParaView's own rows: files that no reader's CanReadFile accepts.
for name in ("random.mhd", "random.tif"):
    try:
        simple.OpenDataFile(path(name))
        message = ""
    except RuntimeError as exc:
        message = str(exc)
    C.check("No reader found" in message and name in message,
            "OpenDataFile(%s): '%s' (ParaView's own answer)" % (name, message.strip()))
random_mha = write("random.mha", bytes(random.getrandbits(8) for _ in range(100000)))
try:
    simple.OpenDataFile(random_mha)
    message = ""
except RuntimeError as exc:
    message = str(exc)
C.check("No reader found" in message, "OpenDataFile(random.mha): '%s'" % message.strip())
C.finish()
