"""ExtractVoxels as the FIRST consumer of a split DimensionReduction: the pipeline gives the
same voxels whichever consumer updates it first.

A consumer that asks a split filter of the suite for an extent of its own (ExtractVoxels
asks for the voxels its process owns) used to get a piece of that extent cut along another
axis (the executive splits an extent asked of several pieces; the filter cropped its output
to that part), and ExtractVoxels then failed with "The input's pieces do not cover the block
this process needs" unless a representation had updated the volume before.

  pvbatch mpi_first_consumer_check.py --reference DIR
      one process: the real brain (ch2 + AAL + Brodmann, every 3rd voxel: 61 x 73 x 61),
      two chains, DimensionReduction computing the features itself and MultichannelFeatures
      -> DimensionReduction (PCA 6D -> 3D); ExtractVoxels on each, never updated before,
      at voxels on every piece of 2-, 3- and 4-process splits and on both sides of each
      piece boundary; checks each extracted voxel against the fetched volume at its id and
      writes DIR/answers.json.
  mpiexec -np R pvbatch --mpi mpi_first_consumer_check.py --compare DIR
      the same on R processes, ExtractVoxels updated first (nothing else updates the
      chain before it): the same voxels, coordinates and channels bit for bit.
Test driver: mpi_reference_compare.sh (CTest pvbatch.test_mpi_first_consumer).
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
from client_server_loop_check import probed_voxels  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

SUBSAMPLE = 3
REDUCTION = dict(ReferenceSampleSize=3000, RandomSeed=7)


def chain(mce, keep_features):
    volume = T.brain_subset(SUBSAMPLE)
    _, red = mce.reduce_multichannel(volume, "PCA", "6D", output_dimension=3,
                                     keep_features=keep_features, **REDUCTION)
    return red


def extracted(data):
    """{voxel id: [coordinates..., channels...]} of an ExtractVoxels output."""
    pd = data.GetPointData()
    ids = pd.GetArray("VoxelId")
    coords = pd.GetArray("ReducedCoordinates")
    names = [n for n in T.BRAIN if pd.GetArray(n)]
    out = {}
    for p in range(data.GetNumberOfPoints() if ids else 0):
        out[str(int(ids.GetValue(p)))] = (list(coords.GetTuple3(p)) +
                                          [pd.GetArray(n).GetTuple1(p) for n in names])
    return out


def main():
    args = T.reference_compare_parser()[0].parse_args()
    mce = T.load_plugin(globals())
    processes, C = T.parallel_checker("mpi_first_consumer_check")
    dims = [61, 73, 61]
    voxels = probed_voxels(dims)
    ids = [i + dims[0] * (j + dims[1] * k) for i, j, k in voxels]
    answers = {}
    for keep in (False, True):
        name = "MultichannelFeatures -> DimensionReduction" if keep else "DimensionReduction"
        red = chain(mce, keep)
        extract = servermanager.filters.ExtractVoxels(Input=red)
        extract.VoxelIds = ids
        extract.UpdatePipeline()  # the first update of the chain
        got = extracted(servermanager.Fetch(extract))
        C.check(sorted(int(v) for v in got) == sorted(ids),
                "%s: ExtractVoxels updated first gives the %d listed voxels (got %d)"
                % (name, len(ids), len(got)))
        answers[name] = got
        if args.reference:
            image = servermanager.Fetch(red)
            pd = image.GetPointData()
            C.check(list(image.GetDimensions()) == dims, "the volume is %s" % dims)
            wrong = [v for v, values in got.items()
                     if values != list(pd.GetArray("ReducedCoordinates").GetTuple3(int(v))) +
                     [pd.GetArray(n).GetTuple1(int(v)) for n in T.BRAIN]]
            C.check(not wrong, "%s: each extracted voxel holds the volume's own coordinates "
                    "and channels at its id (wrong: %s)" % (name, wrong[:5]))
        for proxy in (extract, red):
            simple.Delete(proxy)
    if args.reference:
        os.makedirs(args.reference, exist_ok=True)
        with open(os.path.join(args.reference, "answers.json"), "w") as f:
            json.dump(answers, f)
        C.finish()
    with open(os.path.join(args.compare, "answers.json")) as f:
        reference = json.load(f)
    for name, got in answers.items():
        differ = [v for v in reference[name] if reference[name][v] != got.get(v)]
        C.check(not differ, "%s on %d processes: the same %d voxels, coordinates and channels "
                "bit for bit as one process (differ: %s)"
                % (name, processes, len(reference[name]), differ[:5]))
    C.finish_parallel()


main()
