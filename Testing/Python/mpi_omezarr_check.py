"""The OME-Zarr reader split over MPI processes: each reads its own piece's chunks.

    pvbatch mpi_omezarr_check.py --write DIR [--upsample F] [--chunk N]   (or --reference DIR)
        one process: writes the real 3-channel brain (upsampled F times along each axis by
        repetition, F = 1 by default) as DIR/brain.ome.zarr (c z y x, blosc, N^3 chunks,
        N = 32 by default) and the source as DIR/brain.npy;
    mpiexec -np R pvbatch --mpi mpi_omezarr_check.py --compare DIR [--bytes-table FILE]
        R processes (R = 1 included): ParaView asks each process for its piece; each
        process's piece (fetched from it) must equal the source's voxels at its extent, the
        pieces must cover the volume, and each process must have read only the chunks its
        piece meets: BytesRead of process r equals the bytes of those chunk files (1/R of
        the whole plus the chunks cut by the boundaries between pieces, read by both sides). Prints per process: extent, bytes read, share of the
        whole, time; --bytes-table appends one JSON line with them.
"""
import argparse
import glob
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

T.load_plugin({})
import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--write", "--reference", dest="write")  # mpi_reference_compare.sh
parser.add_argument("--compare")
parser.add_argument("--upsample", type=int, default=1)
parser.add_argument("--chunk", type=int, default=32)
parser.add_argument("--bytes-table")
args = parser.parse_args()

C = T.Checker("mpi_omezarr_check")


if args.write:
    import omezarr_testing as Z

    os.makedirs(args.write, exist_ok=True)
    brain = Z.brain_arrays()
    f = args.upsample
    if f > 1:
        brain = brain.repeat(f, axis=1).repeat(f, axis=2).repeat(f, axis=3)
    np.save(os.path.join(args.write, "brain.npy"), brain)
    Z.write_image(os.path.join(args.write, "brain.ome.zarr"), [brain],
                  scales=[[1.0, 1.0 / f, 1.0 / f, 1.0 / f]], chunks=(1,) + (args.chunk,) * 3)
    print("wrote %s: %s voxels x %d channels, chunks %d^3"
          % (args.write, brain.shape[1:], brain.shape[0], args.chunk))
    C.finish()

folder = os.path.join(args.compare, "brain.ome.zarr")
brain = np.load(os.path.join(args.compare, "brain.npy"), mmap_mode="r")
with open(os.path.join(folder, "0", ".zarray")) as f:
    chunks = json.load(f)["chunks"]
sizes = {}
for path in glob.glob(os.path.join(folder, "0", "*.*.*.*")):
    sizes[tuple(int(v) for v in os.path.basename(path).split("."))] = os.path.getsize(path)
total = sum(sizes.values())

R = T.local_processes()
start = time.time()
reader = simple.OpenDataFile(folder)
reader.ResolutionLevel = 0
reader.UpdatePipeline()
elapsed = time.time() - start
pieces = [servermanager.Fetch(reader, r) for r in range(R)] if R > 1 else [
    servermanager.Fetch(reader)]
nz, ny, nx = brain.shape[1:]
covered = np.zeros((nz, ny, nx), dtype=bool)
rows = []
for r, piece in enumerate(pieces):
    e = piece.GetExtent()
    got_bytes = piece.GetFieldData().GetArray("BytesRead").GetValue(0)
    # The chunk files the piece's extent meets (every channel).
    met = [size for (c, cz, cy, cx), size in sizes.items()
           if cz * chunks[1] <= e[5] and (cz + 1) * chunks[1] > e[4] and
           cy * chunks[2] <= e[3] and (cy + 1) * chunks[2] > e[2] and
           cx * chunks[3] <= e[1] and (cx + 1) * chunks[3] > e[0]]
    own = sum(met)
    C.check(got_bytes == own, "process %d of %d: extent %s, BytesRead %d = the %d of %d chunk "
            "files its extent meets (%d), %.3f of all %d chunk bytes"
            % (r, R, e, got_bytes, len(met), len(sizes), own, got_bytes / float(total), total))
    rows.append({"process": r, "extent": list(e), "bytes_read": int(got_bytes),
                 "share": got_bytes / float(total), "chunks": len(met),
                 "chunk_share": len(met) / float(len(sizes))})
    pd = piece.GetPointData()
    equal = pd.GetNumberOfArrays() == 3
    for c in range(min(3, pd.GetNumberOfArrays())):
        values = vtk_to_numpy(pd.GetArray(c)).reshape(e[5] - e[4] + 1, e[3] - e[2] + 1,
                                                       e[1] - e[0] + 1)
        equal = equal and np.array_equal(
            values, brain[c, e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1])
    C.check(equal, "process %d: its 3 channels equal the source at its extent" % r)
    covered[e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1] = True
C.check(covered.all(), "the %d pieces cover the %s volume" % (R, (nx, ny, nz)))
if R > 1:
    # A piece reads whole chunks: those cut by a boundary between pieces are read by both
    # sides, so a share is 1/R plus those chunks (measured above, chunk for chunk).
    largest = max(row["share"] for row in rows)
    C.check(largest < 1.0, "no process read the whole level (largest share %.3f, 1/%d = %.3f)"
            % (largest, R, 1.0 / R))
print("OME-Zarr %s on %d process(es): %.2f s; bytes read per process %s of %d; shares %s; "
      "chunk files per process %s of %d"
      % ((nx, ny, nz), R, elapsed, [row["bytes_read"] for row in rows], total,
         ["%.3f" % row["share"] for row in rows], [row["chunks"] for row in rows], len(sizes)))
if args.bytes_table:
    with open(args.bytes_table, "a") as f:
        f.write(json.dumps({"processes": R, "voxels": [nx, ny, nz], "total_bytes": total,
                            "seconds": elapsed, "pieces": rows}) + "\n")
C.finish_parallel()
