"""The suite's filters under ParaView's parallel engine give the one-process answer.

Run twice on the real 3-channel brain (Colin27 ch2 + AAL + Brodmann):
  pvbatch mpi_parallel_check.py --reference DIR
      one process: writes the best view direction (full resolution), and the features
      (24D) and reduced coordinates (Isomap) of the brain subsampled by 3 to DIR;
  mpiexec -np R pvbatch --mpi mpi_parallel_check.py --compare DIR
      R processes, each holding a piece (ParaView splits the volume; the filters ask for
      ghost layers and combine global statistics, top-N lists and the reference sample
      across processes): checks the view direction within 0.5 degrees, the features, the
      background mask (Foreground: from the channels' global ranges; the reference sample
      is drawn from its foreground) and the reduced coordinates of every voxel equal to the
      reference (float tolerance; the mask exactly), and prints the times of each stage;
      the same for DimensionReduction on the channels (the fused path: each process
      computes its piece's features a slab at a time and places its own voxels), whose
      one-process coordinates also equal the chain's;
      and both on the brain resampled by ParaView's ResampleToImage, which splits its
      output its own way (DIY blocks) whatever extent the filters ask for: each process
      then assembles its block from the others' pieces; and DimensionReduction on the
      features of the resampled brain, which asks its piece of MultichannelFeatures, which
      must still ask ResampleToImage the same extent on every process (vtkPResampleToImage
      corrupts its heap otherwise: mcvPieces.h).
With --thin, a 2 x 2 x 2 synthetic volume instead (PCA): more processes than the volume
splits in, so some own no voxel and must take part with nothing.
Test driver: test_mpi.sh. No numpy in Debian's ParaView Python: plain arrays.
"""
import array
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

SUBSAMPLE = 3
REDUCTION = dict(Method="Isomap", OutputDimension=3, NumberOfNeighbors=12,
                 NumberOfLandmarks=200, ReferenceSampleSize=3000, RandomSeed=7)
THIN_REDUCTION = dict(Method="PCA", OutputDimension=3, ReferenceSampleSize=32, RandomSeed=7)


def brain():
    t1 = simple.OpenDataFile(T.data_file("ch2.nii.gz"))
    aal = simple.OpenDataFile(T.data_file("aal.nii.gz"))
    brodmann = simple.OpenDataFile(T.data_file("brodmann.nii.gz"))
    return simple.AppendAttributes(Input=[t1, aal, brodmann])


def thin_volume():
    """2 x 2 x 2 voxels: fewer slices than processes, so some process owns no
    voxel of the volume (ParaView gives it a piece of ghost layers only)."""
    wavelet = simple.Wavelet(WholeExtent=[0, 1, 0, 1, 0, 1])
    return simple.Calculator(Input=wavelet, ResultArrayName="Doubled", Function="2*RTData^2")


def timed(proxy):
    start = time.time()
    proxy.UpdatePipeline()
    return time.time() - start


# The arrays compared, with their array module type codes (float32, uint8).
COMPARED = (("Features", "f"), ("Foreground", "B"), ("ReducedCoordinates", "f"))
FUSED_COMPARED = (("Foreground", "B"), ("ReducedCoordinates", "f"))
RESAMPLED_COMPARED = (("Features", "f"), ("Foreground", "B"))
RESAMPLED_DIMS = [40, 48, 40]


def values_of(vtk_array, typecode="f"):
    """The values of a VTK array of that type (float32 by default), tuple-major."""
    out = array.array(typecode)
    out.frombytes(bytes(memoryview(vtk_array)))
    return out


def piece_indices(piece, dims):
    """Whole-volume linear index of every point of an image piece, in point order."""
    e = piece.GetExtent()
    return [i + dims[0] * (j + dims[1] * k)
            for k in range(e[4], e[5] + 1)
            for j in range(e[2], e[3] + 1)
            for i in range(e[0], e[1] + 1)]


def main():
    parser, _ = T.reference_compare_parser()
    parser.add_argument("--thin", action="store_true",
                        help="a 2 x 2 x 2 synthetic volume instead of the brain")
    args = parser.parse_args()
    mce = T.load_plugin(globals())
    from paraview.simple import BestViewpoint, DimensionReduction, MultichannelFeatures
    R, C = T.parallel_checker("mpi_parallel_check")
    timings = {}

    merged = thin_volume() if args.thin else brain()
    view = BestViewpoint(Input=merged)
    timings["read+view"] = timed(view)
    view.UpdatePropertyInformation()
    direction = [float(x) for x in view.GetPropertyValue("BestViewDirection")]
    visible_bounds = [float(x) for x in view.GetPropertyValue("VisibleBounds")]
    flat = [float(x) for x in view.GetProperty("VisibleSupport")]
    support = [flat[i:i + 3] for i in range(0, len(flat), 3)]

    if args.thin:
        sub = merged  # each process's block: ghost layers around a piece it may not own
    else:
        sub = simple.ExtractSubset(Input=merged)
        sub.SampleRateI = sub.SampleRateJ = sub.SampleRateK = SUBSAMPLE
    feats = MultichannelFeatures(Input=sub)
    feats.FeatureSet = "24D"
    messages = [T.Messages(feats)]
    timings["features"] = timed(feats)
    reduction = DimensionReduction(Input=feats)
    messages.append(T.Messages(reduction))
    for key, value in (THIN_REDUCTION if args.thin else REDUCTION).items():
        setattr(reduction, key, value)
    timings["reduction"] = timed(reduction)
    fused = DimensionReduction(Input=sub, FeatureSet="24D")
    messages.append(T.Messages(fused))
    for key, value in (THIN_REDUCTION if args.thin else REDUCTION).items():
        setattr(fused, key, value)
    timings["fused reduction"] = timed(fused)
    if not args.thin:
        resampled = simple.ResampleToImage(Input=merged, UseInputBounds=1,
                                           SamplingDimensions=RESAMPLED_DIMS)
        resampled_feats = MultichannelFeatures(Input=resampled, FeatureSet="6D")
        messages.append(T.Messages(resampled_feats))
        timings["resampled features"] = timed(resampled_feats)
        resampled_fused = DimensionReduction(Input=resampled, FeatureSet="24D")
        messages.append(T.Messages(resampled_fused))
        for key, value in REDUCTION.items():
            setattr(resampled_fused, key, value)
        timings["resampled fused reduction"] = timed(resampled_fused)
        # A split filter asks its input (a filter of the suite) for its piece, which then
        # asks ResampleToImage: that request must stay the same on every process.
        resampled_chain = DimensionReduction(Input=resampled_feats)
        messages.append(T.Messages(resampled_chain))
        for key, value in REDUCTION.items():
            setattr(resampled_chain, key, value)
        timings["resampled chain reduction"] = timed(resampled_chain)
    errors = [e for m in messages for e in m.errors]
    C.check(not errors, "no error from the features or the reductions %s" % errors)

    if args.reference:
        assert R == 1, "the reference run is one process"
        os.makedirs(args.reference, exist_ok=True)
        image = reduction.GetClientSideObject().GetOutputDataObject(0)
        info = {"direction": direction, "visible_bounds": visible_bounds, "support": support,
                "origin": list(image.GetOrigin()),
                "spacing": list(image.GetSpacing()), "dims": list(image.GetDimensions()),
                "features": image.GetPointData().GetArray("Features").GetNumberOfComponents(),
                "timings": timings}
        with open(os.path.join(args.reference, "reference.json"), "w") as f:
            json.dump(info, f)
        for name, code in COMPARED:
            with open(os.path.join(args.reference, name + ".values"), "wb") as f:
                values_of(image.GetPointData().GetArray(name), code).tofile(f)
        fused_image = fused.GetClientSideObject().GetOutputDataObject(0)
        for name, code in FUSED_COMPARED:
            with open(os.path.join(args.reference, "fused_" + name + ".values"), "wb") as f:
                values_of(fused_image.GetPointData().GetArray(name), code).tofile(f)
        if not args.thin:
            for proxy, compared in ((resampled_feats, RESAMPLED_COMPARED),
                                    (resampled_fused, (("ReducedCoordinates", "f"),))):
                out = proxy.GetClientSideObject().GetOutputDataObject(0)
                for name, code in compared:
                    with open(os.path.join(args.reference, "resampled_" + name + ".values"),
                              "wb") as f:
                        values_of(out.GetPointData().GetArray(name), code).tofile(f)
            out = resampled_chain.GetClientSideObject().GetOutputDataObject(0)
            with open(os.path.join(args.reference, "resampled_chain_ReducedCoordinates.values"),
                      "wb") as f:
                values_of(out.GetPointData().GetArray("ReducedCoordinates")).tofile(f)
        chain = values_of(image.GetPointData().GetArray("ReducedCoordinates"))
        own = values_of(fused_image.GetPointData().GetArray("ReducedCoordinates"))
        span = max(chain) - min(chain)
        worst = max(abs(a - b) for a, b in zip(chain, own))
        C.check(len(own) == len(chain) and worst <= 1e-5 * span,
                "fused coordinates equal the chain's (worst %.2e of a range %.3g)" % (worst, span))
        mask = values_of(image.GetPointData().GetArray("Foreground"), "B")
        C.check(args.thin or 0 < sum(mask) < len(mask), "the mask has background and foreground (%d of %d "
                "voxels foreground)" % (sum(mask), len(mask)))
        C.check(image.GetNumberOfPoints() >= (8 if args.thin else 100000),
                "reference of %d voxels written" % image.GetNumberOfPoints())
        print("timings (1 process): " + ", ".join("%s %.2f s" % kv for kv in timings.items()))
        C.finish()

    with open(os.path.join(args.compare, "reference.json")) as f:
        ref = json.load(f)
    angle = T.angle_deg(direction, ref["direction"], unsigned=True)
    C.check(angle <= 0.5, "best view direction within 0.5 deg of one process (%.2e deg)"
            % angle)
    C.check(visible_bounds == ref["visible_bounds"],
            "VisibleBounds equal one process's: %s" % visible_bounds)
    # each direction's furthest visible voxel: as far along it as one process's (a tie may
    # pick another voxel at that distance)
    gaps = [abs(sum((p[a] - r[a]) * d[a] for a in range(3)))
            for p, r, d in zip(support, ref["support"], T.support_directions())]
    C.check(len(support) == len(ref["support"]) == 128 and max(gaps) <= 1e-6,
            "VisibleSupport reaches as far as one process's along each of its %d directions "
            "(largest difference %.1e)" % (len(support), max(gaps) if gaps else -1))

    # Every process's piece, brought to the first one, placed by its extent.
    dims = ref["dims"]
    compare_pieces(C, reduction, R, dims, COMPARED, args.compare, "")
    compare_pieces(C, fused, R, dims, FUSED_COMPARED, args.compare, "fused_")
    if not args.thin:
        compare_pieces(C, resampled_feats, R, RESAMPLED_DIMS, RESAMPLED_COMPARED, args.compare,
                       "resampled_")
        compare_pieces(C, resampled_fused, R, RESAMPLED_DIMS, (("ReducedCoordinates", "f"),),
                       args.compare, "resampled_")
        compare_pieces(C, resampled_chain, R, RESAMPLED_DIMS, (("ReducedCoordinates", "f"),),
                       args.compare, "resampled_chain_")
    print("timings (%d processes): " % R + ", ".join("%s %.2f s" % kv for kv in timings.items()))
    print("timings (1 process):   " + ", ".join("%s %.2f s" % kv
                                                for kv in ref["timings"].items()))
    C.finish_parallel()


def compare_pieces(C, proxy, R, dims, compared, folder, prefix):
    """Every process's piece of `proxy`, brought to the first one and placed by its
    extent, against the one-process arrays `compared` in `folder`."""
    total = dims[0] * dims[1] * dims[2]
    pieces = [servermanager.Fetch(proxy, r) for r in range(R)]
    print("%s piece extents: %s" % (prefix, [tuple(p.GetExtent()) for p in pieces]))
    covered = set()
    for piece in pieces:
        covered.update(piece_indices(piece, dims))
    C.check(len(covered) == total, "%sthe %d pieces cover the %s volume (%d of %d voxels)"
            % (prefix, R, dims, len(covered), total))
    for name, code in compared:
        expected = array.array(code)
        with open(os.path.join(folder, prefix + name + ".values"), "rb") as f:
            expected.frombytes(f.read())
        span = max(expected) - min(expected)
        worst = 0.0
        for piece in pieces:
            if piece.GetNumberOfPoints() == 0:
                continue  # a process with no voxel (more processes than the volume splits in)
            got_array = piece.GetPointData().GetArray(name)
            if not C.check(got_array is not None, "%s in every piece" % name):
                break
            got = values_of(got_array, code)
            width = got_array.GetNumberOfComponents()
            for row, v in enumerate(piece_indices(piece, dims)):
                a = got[row * width:(row + 1) * width]
                b = expected[v * width:(v + 1) * width]
                worst = max(worst, max(abs(x - y) for x, y in zip(a, b)))
        C.check(worst <= 1e-4 * span, "%s%s equal to one process on every voxel "
                "(worst difference %.2e of a range %.3g)" % (prefix, name, worst, span))


if __name__ == "__main__":
    main()
