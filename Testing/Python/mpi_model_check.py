"""Reduction models under ParaView's parallel engine: the same model, the same placement and
the same one-fit series on R processes as on one.

  pvbatch mpi_model_check.py --reference DIR
      one process: writes the real brain (Colin27 T1 + AAL, every 3rd voxel) as DIR/fit.vti,
      DIR/half.vti (upper half of the T1 x 1.3) and a 3-step series DIR/step_*.vti (step 2:
      T1 x 1.2); fits PCA and Isomap models on fit.vti (DIR/<method>.mcvmodel); saves the
      coordinates and ModelDistance of each model applied to half.vti and of FitTime One time
      step and All time steps on the series (DIR/reference.npz);
  mpiexec -np R pvbatch --mpi mpi_model_check.py --compare DIR
      R processes: a fit of fit.vti saves a model file byte-identical to the one-process
      one; each model applied to half.vti gives the reference coordinates, ModelDistance and
      out-of-model count bit for bit (every process's piece placed by its extent); FitTime
      One time step and All time steps give the reference coordinates at every step.
Test driver: mpi_reference_compare.sh.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

METHODS = ("PCA", "Isomap")
SAMPLE = 3000


def write_vti(path, t1, aal):
    T.write_vti(path, [("ch2", t1), ("aal", aal)])


def gathered(proxy, names, shape, R):
    """{name: whole-volume array} from every process's piece of `proxy` (placed by extent);
    None for a name missing on a non-empty piece."""
    out = {}
    for r in range(R):
        piece = servermanager.Fetch(proxy, r) if R > 1 else servermanager.Fetch(proxy)
        if piece.GetNumberOfPoints() == 0:
            continue
        e = piece.GetExtent()
        box = (slice(e[4], e[5] + 1), slice(e[2], e[3] + 1), slice(e[0], e[1] + 1))
        for name in names:
            array = piece.GetPointData().GetArray(name)
            if array is None:
                out[name] = None
                continue
            values = vtk_to_numpy(array)
            comps = array.GetNumberOfComponents()
            if name not in out:
                out[name] = np.zeros(shape + ((comps,) if comps > 1 else ()), dtype=values.dtype)
            if out[name] is not None:
                piece_shape = (e[5] - e[4] + 1, e[3] - e[2] + 1, e[1] - e[0] + 1)
                out[name][box] = values.reshape(piece_shape + ((comps,) if comps > 1 else ()))
    return out


def main():
    args = T.reference_compare_parser()[0].parse_args()
    mce = T.load_plugin(globals())
    R, C = T.parallel_checker("mpi_model_check")
    folder = args.reference or args.compare
    if args.reference:
        os.makedirs(folder, exist_ok=True)
        brain = T.brain_arrays(("ch2", "aal"), step=3).astype(np.float32)
        t1, aal = brain[0], brain[1]
        half = t1.copy()
        half[t1.shape[0] // 2:] *= 1.3
        write_vti(os.path.join(folder, "fit.vti"), t1, aal)
        write_vti(os.path.join(folder, "half.vti"), half, aal)
        for i, factor in enumerate((1.0, 1.0, 1.2)):
            write_vti(os.path.join(folder, "step_%d.vti" % i), t1 * factor, aal)
        shape = t1.shape
    else:
        reference = np.load(os.path.join(folder, "reference.npz"))
        shape = tuple(reference["shape"])
    results = {"shape": np.array(shape)}
    names = ("ReducedCoordinates", "ModelDistance")

    for method in METHODS:
        source = simple.OpenDataFile(os.path.join(folder, "fit.vti"))
        _, fitted = mce.reduce_multichannel(source, method, "6D", ReferenceSampleSize=SAMPLE)
        name = ("%s.mcvmodel" if args.reference else "mpi_%s.mcvmodel") % method
        model = mce.save_model(fitted, os.path.join(folder, name))
        if args.compare:
            # The normalisation's statistics are summed in another order across processes
            # (offsets and scales agree to ~1e-13): the models agree to that rounding.
            mine = mce.read_model(model)
            theirs = mce.read_model(os.path.join(folder, method + ".mcvmodel"))
            same_layout = all(mine[k][f] == theirs[k][f] for k, f in (
                ("features", "channels"), ("features", "names"), ("reduction", "method"),
                ("reduction", "references"), ("reduction", "usedColumns")))
            scales = [abs(a - b) / max(abs(b), 1e-30) for k in ("offset", "scale")
                      for a, b in zip(mine["features"][k], theirs["features"][k])]
            C.check(same_layout and max(scales) < 1e-10,
                    "%s: the model fitted on %d processes has one process's channels, "
                    "features, method and references, its normalisation within %.1e"
                    % (method, R, max(scales)))
        model = os.path.join(folder, method + ".mcvmodel")
        changed = simple.OpenDataFile(os.path.join(folder, "half.vti"))
        _, applied = mce.reduce_multichannel(changed, model=model)
        applied.UpdatePipeline()
        applied.UpdatePropertyInformation()
        got = gathered(applied, names, shape, R)
        count = applied.GetProperty("NumberOfOutOfModelVoxels").GetElement(0)
        if args.reference:
            for n in names:
                results["%s_%s" % (method, n)] = got[n]
            results["%s_count" % method] = np.array(count)
        else:
            for n in names:
                want = reference["%s_%s" % (method, n)]
                C.check(got.get(n) is not None and np.array_equal(got[n], want),
                        "%s applied on %d processes: %s equals one process's bit for bit"
                        % (method, R, n))
            C.check(count == int(reference["%s_count" % method]),
                    "%s: the out-of-model count is the whole volume's on every process (%d)"
                    % (method, count))
        for p in (applied, changed, fitted, source):
            simple.Delete(p)

    series = simple.OpenDataFile([os.path.join(folder, "step_%d.vti" % i) for i in range(3)])
    series.UpdatePipelineInformation()
    for fit_time, label in (("One time step", "series"), ("All time steps", "all_steps")):
        _, one = mce.reduce_multichannel(series, "PCA", "6D", ReferenceSampleSize=SAMPLE)
        one.FitTime = fit_time
        one.FitTimeStep = 0
        for t in series.TimestepValues:
            forced = simple.ForceTime(Input=one, ForcedTime=t, IgnorePipelineTime=1)
            forced.UpdatePipeline()
            got = gathered(forced, ("ReducedCoordinates",), shape, R)["ReducedCoordinates"]
            key = "%s_%d" % (label, int(t))
            if args.reference:
                results[key] = got
            else:
                C.check(got is not None and np.array_equal(got, reference[key]),
                        "FitTime %s on %d processes, step %d: the one-process "
                        "coordinates bit for bit" % (fit_time, R, int(t)))
            simple.Delete(forced)
        simple.Delete(one)
    if args.reference:
        np.savez(os.path.join(folder, "reference.npz"), **results)
        C.check(all(results["%s_ReducedCoordinates" % m] is not None for m in METHODS),
                "the reference run wrote its coordinates")
        C.finish()
    else:
        C.finish_parallel()


if __name__ == "__main__":
    main()
