"""The "Gaussian TF Volume" split over MPI processes draws the one-process picture.

  pvbatch mpi_gaussian_tf_check.py --reference DIR
      one process: a 48^3 volume of reduced coordinates (voxel position / 47) under two
      translucent widgets, seen obliquely, per sample and per voxel; screenshots to DIR;
  mpiexec -np R pvbatch --mpi mpi_gaussian_tf_check.py --compare DIR
      R processes: each renders its own piece (per sample: its own coordinate texture and
      uniforms), IceT composites in depth order; checks every pixel against the one-process
      picture (max difference and mean over the image; seams between pieces show up here).
Test driver: test_mpi.sh.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402
import builtins as B  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

N = 48
WIDGETS = [0.3, 0.5, 0.5, 0.12, 1.0, 0.2, 0.1, 0.12, 0.7, 0.5, 0.5, 0.12, 0.1, 0.5, 1.0, 0.12]


def render(out_dir, label, mode):
    mce = T.load_plugin(globals())
    wavelet = simple.Wavelet(WholeExtent=[0, N - 1] * 3)
    calc = simple.Calculator(Input=wavelet, ResultArrayName="ReducedCoordinates",
                             ResultArrayType="Float", Function="coords/%d" % (N - 1))
    view = G.black_view((360, 300))
    display = mce.show_gaussian_tf(calc, view, widgets=WIDGETS)
    display.Classification = mode
    display.Jittering = 0  # the same samples on every process count
    simple.Render(view)
    view.CameraFocalPoint = [(N - 1) / 2.0] * 3
    view.CameraPosition = [(N - 1) / 2.0 + 70, (N - 1) / 2.0 + 45, (N - 1) / 2.0 + 90]
    view.CameraViewUp = [0, 1, 0]
    simple.Render(view)
    return G.Shot(view, os.path.join(out_dir, "%s_%s.png" % (label, mode.replace(" ", "_"))))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--reference")
    parser.add_argument("--compare")
    args = parser.parse_args()
    ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
    C = T.Checker("mpi_gaussian_tf_check (%d processes)" % ranks)
    for mode in ("Per sample", "Per voxel"):
        if args.reference:
            s = render(args.reference, "reference", mode)
            C.check(s.max_channel() > 60, "%s: one process draws the volume" % mode)
            continue
        s = render(args.compare, "ranks%d" % ranks, mode)
        from vtkmodules.vtkIOImage import vtkPNGReader

        reader = vtkPNGReader()
        reader.SetFileName(os.path.join(args.compare, "reference_%s.png" % mode.replace(" ", "_")))
        reader.Update()
        ref = reader.GetOutput().GetPointData().GetScalars()
        mine = s.scalars
        worst, total = 0, 0
        for i in range(ref.GetNumberOfTuples()):
            d = B.max(abs(a - b) for a, b in zip(ref.GetTuple(i)[:3], mine.GetTuple(i)[:3]))
            worst, total = B.max(worst, d), total + d
        mean = total / float(ref.GetNumberOfTuples())
        print("%s, %d processes: max pixel difference %d, mean %.3f" % (mode, ranks, worst, mean))
        C.check(s.max_channel() > 60, "%s: %d processes draw the volume" % (mode, ranks))
        C.check(mean <= 0.5 and worst <= 40,
                "%s: %d processes draw the one-process picture (max %d, mean %.3f)"
                % (mode, ranks, worst, mean))
    if args.reference:
        C.finish()
    C.finish_parallel()


main()
