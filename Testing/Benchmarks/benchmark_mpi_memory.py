"""One process of the main job's fused reduction under `mpiexec -np R pvbatch --mpi
--symmetric`: every process runs this script, reads the real 3-channel brain
(Colin27 ch2 + AAL + Brodmann), resamples it by F along each axis with ParaView's
ResampleToImage (as Examples/transfer_function.py --upsample F), and runs
DimensionReduction on the channels with the main job's settings (24D, Isomap, reference
sample 10000, K = 10, L = 500, seed 0), each process on its own piece.

Two sources:
  (default) the NIfTI files: every process reads the whole volume (and, for F != 1,
      vtkPResampleToImage resamples on every process), so no process holds less than the
      whole channels;
  --volume FILE.vti: the merged (and resampled) channels saved once by
      `--write-volume FILE.vti` (one process, uncompressed appended raw data), read with
      vtkXMLImageDataReader, which reads only the extent asked of it: each process reads
      and holds only its block when DimensionReduction asks for its piece plus one ghost
      layer (Filters/Common/mcvPieces.h; docs/benchmarks.md §7.2 says when it does).

Each process writes to DIR:
  rank<r>.f32   its piece's ReducedCoordinates (float32, x fastest over its extent)
  rank<r>.json  its extent, the whole dimensions, its stage times, its resident size once
                ParaView and the plugin are loaded and before anything is read (the
                baseline), its peak resident memory (ru_maxrss) after each stage, and
                each stage's own peak (VmHWM restarted at the stage's start) with the
                resident sizes it started from and ended with
benchmark_mpi_memory.sh runs it for R = 1, 2, 4 and compares every piece with the
one-process coordinates, voxel by voxel, and the peaks with the one-process run's.
"""
import argparse
import json
import os
import resource
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402


def peak_gib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / float(1 << 20)


def status_gib(key):
    """VmRSS / VmHWM of this process from /proc/self/status, in GiB."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / float(1 << 20)
    return float("nan")


def reset_peak():
    """Restarts VmHWM at the current resident size (Linux >= 4.0: clear_refs 5), so that
    a stage's own peak is not hidden by an earlier stage's (ru_maxrss never falls)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def whole_dims(proxy):
    """The whole grid's dimensions from the pipeline information each process holds (in
    symmetric mode GetDataInformation describes only what the first process gathered)."""
    from paraview.vtk import vtkStreamingDemandDrivenPipeline as SDDP

    algorithm = proxy.GetClientSideObject()
    e = algorithm.GetOutputInformation(0).Get(SDDP.WHOLE_EXTENT())
    return [e[2 * a + 1] - e[2 * a] + 1 for a in range(3)]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--upsample", type=float, default=2.0)
    parser.add_argument("--method", default="Isomap", choices=("Isomap", "PCA"))
    parser.add_argument("--volume", help="read the channels from this .vti instead of NIfTI")
    parser.add_argument("--write-volume", help="save the merged (resampled) channels here "
                        "as .vti and stop (one process)")
    parser.add_argument("--output")
    args = parser.parse_args()
    if not (args.output or args.write_volume):
        parser.error("--output or --write-volume is needed")
    T.load_plugin(globals())
    from paraview.simple import DimensionReduction
    baseline = round(status_gib("VmRSS"), 3)

    controller = servermanager.vtkProcessModule.GetProcessModule().GetGlobalController()
    rank, ranks = controller.GetLocalProcessId(), controller.GetNumberOfProcesses()
    stages, peaks, stage_start, stage_peak, stage_end = {}, {}, {}, {}, {}

    def timed(name, proxy):
        stage_start[name] = round(status_gib("VmRSS"), 3)
        reset = reset_peak()
        start = time.time()
        proxy.UpdatePipeline()
        stages[name] = round(time.time() - start, 3)
        peaks[name] = round(peak_gib(), 3)
        stage_peak[name] = round(status_gib("VmHWM"), 3) if reset else None
        stage_end[name] = round(status_gib("VmRSS"), 3)

    if args.volume:
        # Not updated on its own: asked for piece r of R, the reader would read the piece
        # without the ghost layer, then again the block DimensionReduction asks for.
        volume = simple.XMLImageDataReader(FileName=[args.volume])
        volume.UpdatePipelineInformation()
    else:
        readers = [simple.OpenDataFile(T.data_file(n))
                   for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
        volume = simple.MergeChannels(Input=readers)
        timed("read", volume)
        dims = whole_dims(volume)
        if args.upsample != 1.0:
            volume = simple.ResampleToImage(
                Input=volume, UseInputBounds=1,
                SamplingDimensions=[max(1, int(round(d * args.upsample))) for d in dims])
            timed("upsample", volume)
    if args.write_volume:
        # Uncompressed appended raw data: the reader seeks to the rows of the extent it is
        # asked for (zlib blocks would be read and inflated whole).
        start = time.time()
        simple.SaveData(args.write_volume, proxy=volume, DataMode="Appended",
                        EncodeAppendedData=0, CompressorType="None")
        print("wrote %s: %s voxels, %.2f GiB, in %.1f s (upsample %.1f s)"
              % (args.write_volume, "x".join(str(d) for d in whole_dims(volume)),
                 os.path.getsize(args.write_volume) / float(1 << 30), time.time() - start,
                 stages.get("upsample", 0.0)))
        return
    reduction = DimensionReduction(Input=volume, FeatureSet="24D", Method=args.method,
                                   OutputDimension=3, ReferenceSampleSize=10000,
                                   NumberOfNeighbors=10, NumberOfLandmarks=500, RandomSeed=0)
    timed("reduction", reduction)

    image = reduction.GetClientSideObject().GetOutputDataObject(0)
    coordinates = image.GetPointData().GetArray("ReducedCoordinates")
    os.makedirs(args.output, exist_ok=True)
    with open(os.path.join(args.output, "rank%d.f32" % rank), "wb") as f:
        if coordinates is not None and coordinates.GetNumberOfTuples() > 0:
            f.write(memoryview(coordinates))  # the buffer itself, no copy
    info = {"rank": rank, "ranks": ranks, "extent": list(image.GetExtent()),
            "points": image.GetNumberOfPoints(),
            "whole_dims": whole_dims(reduction),
            "threads": int(os.environ.get("OMP_NUM_THREADS", "0")),
            "source": "vti" if args.volume else "nifti", "method": args.method,
            "baseline_rss_gib": baseline,
            "stage_seconds": stages, "stage_peak_rss_gib": peaks,
            "stage_start_rss_gib": stage_start, "stage_own_peak_gib": stage_peak,
            "stage_end_rss_gib": stage_end,
            "peak_rss_gib": peak_gib()}
    with open(os.path.join(args.output, "rank%d.json" % rank), "w") as f:
        json.dump(info, f)
    print("rank %d of %d: %d points, baseline %.2f GiB, peak %.2f GiB, %s, stage start/peak GiB %s %s"
          % (rank, ranks, info["points"], baseline, info["peak_rss_gib"], stages, stage_start,
             stage_peak))
    sys.stdout.flush()


if __name__ == "__main__":
    main()
