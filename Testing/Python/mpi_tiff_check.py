"""An ImageJ hyperstack, and a time series of one hyperstack per frame, read by the checked
TIFF reader under ParaView's parallel engine.

  pvbatch mpi_tiff_check.py --reference DIR
      one process: writes DIR/brain_tzcyx.tif (the real 3-channel brain on a 2 mm grid,
      ImageJ TZCYX, uint16, 2 frames: frame 1 = frame 0 + 100, zlib-compressed pages of 8
      rows per strip), the same frames as DIR/brain_t0.tif and brain_t1.tif (ZCYX, a time
      series of two files) and the written values DIR/written.npy; reads each source whole
      at both times and checks it against them (bit for bit);
  mpiexec -np R pvbatch --mpi mpi_tiff_check.py --compare DIR
      R processes, each reading its piece (the reader produces any sub-extent): each
      process's piece, brought to the first process (Fetch of that process) and placed by
      its extent, equals the written values at both times (ForceTime); the pieces cover the
      volume (sharing boundary layers only); with R > 1 no process holds the whole volume.
Test driver: mpi_reference_compare.sh.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

NAMES = ("C1", "C2", "C3")
TIMES = (0.0, 0.25)


def piece_arrays(image):
    e = image.GetExtent()
    shape = (e[5] - e[4] + 1, e[3] - e[2] + 1, e[1] - e[0] + 1)
    pd = image.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)).reshape(shape)
            for i in range(pd.GetNumberOfArrays())}


def write(folder):
    import tifffile

    source = []
    for n in ("ch2", "aal", "brodmann"):
        reader = simple.OpenDataFile(T.data_file(n + ".nii.gz"))
        image = servermanager.Fetch(reader, 0)
        values = list(piece_arrays(image).values())[0]
        source.append(np.ascontiguousarray(values[::2, ::2, ::2]).astype(np.uint16))
        simple.Delete(reader)
    f0 = np.stack(source)                                    # (C, Z, Y, X)
    written = np.stack([f0, f0 + 100])                       # (T, C, Z, Y, X)
    tifffile.imwrite(os.path.join(folder, "brain_tzcyx.tif"),
                     np.ascontiguousarray(written.transpose(0, 2, 1, 3, 4)), imagej=True,
                     compression="zlib", rowsperstrip=8, resolution=(1 / 2.0, 1 / 2.0),
                     metadata={"axes": "TZCYX", "spacing": 2.0, "unit": "um",
                               "finterval": TIMES[1]})
    for f in range(2):  # the same frames as a time series of one hyperstack per frame
        tifffile.imwrite(os.path.join(folder, "brain_t%d.tif" % f),
                         np.ascontiguousarray(written[f].transpose(1, 0, 2, 3)), imagej=True,
                         compression="zlib", rowsperstrip=8, resolution=(1 / 2.0, 1 / 2.0),
                         metadata={"axes": "ZCYX", "spacing": 2.0, "unit": "um"})
    np.save(os.path.join(folder, "written.npy"), written)
    return written


def main():
    args = T.reference_compare_parser()[0].parse_args()
    T.load_plugin(globals())
    R, C = T.parallel_checker("mpi_tiff_check")
    folder = args.reference or args.compare
    if args.reference:
        os.makedirs(folder, exist_ok=True)
        written = write(folder)
    else:
        written = np.load(os.path.join(folder, "written.npy"))
    for label, files, times in (
            ("hyperstack", ["brain_tzcyx.tif"], TIMES),
            ("series of 2 files", ["brain_t0.tif", "brain_t1.tif"], (0.0, 1.0))):
        check_source(C, R, label, [os.path.join(folder, f) for f in files], times, written)
    if R > 1:
        C.finish_parallel()
    else:
        C.finish()


def check_source(C, R, label, files, times, written):
    """The reader of `files` at each of its `times`, piece by piece, against `written`."""
    _, _, Z, Y, X = written.shape
    reader = simple.CheckedTIFFReader(FileNames=files)
    reader.UpdatePipelineInformation()
    C.check([float(t) for t in reader.TimestepValues] == list(times),
            "%s: time steps %s" % (label, list(reader.TimestepValues)))
    for f, time in enumerate(times):
        forced = simple.ForceTime(Input=reader, ForcedTime=time, IgnorePipelineTime=1)
        forced.UpdatePipeline()
        pieces = [servermanager.Fetch(forced, r) for r in range(R)]
        extents = [tuple(p.GetExtent()) for p in pieces]
        print("%s, frame %d: piece extents %s" % (label, f, extents))
        count = np.zeros((Z, Y, X), dtype=np.int32)
        same = True
        for piece in pieces:
            if piece.GetNumberOfPoints() == 0:
                continue
            e = piece.GetExtent()
            box = (slice(e[4], e[5] + 1), slice(e[2], e[3] + 1), slice(e[0], e[1] + 1))
            count[box] += 1
            got = piece_arrays(piece)
            same = same and list(got.keys()) == list(NAMES) and all(
                np.array_equal(got[n], written[f, c][box]) for c, n in enumerate(NAMES))
        C.check(same, "%s, frame %d: every piece's C1..C3 equal the written values bit for bit"
                % (label, f))
        # Image pieces share their boundary layer of points (VTK's extents): each voxel is
        # in one piece, or two on a shared layer.
        shared = int((count > 1).sum())
        C.check(bool((count >= 1).all()) and shared <= (R - 1) * max(X * Y, Y * Z, X * Z),
                "%s, frame %d: the %d pieces cover the volume (voxels in none: %d; on shared "
                "layers: %d)" % (label, f, R, int((count == 0).sum()), shared))
        if R > 1:
            C.check(all(p.GetNumberOfPoints() < X * Y * Z for p in pieces),
                    "%s, frame %d: no process holds the whole volume (%s points)"
                    % (label, f, [p.GetNumberOfPoints() for p in pieces]))
        simple.Delete(forced)
    simple.Delete(reader)


if __name__ == "__main__":
    main()
