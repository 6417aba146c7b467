"""Reading one OME-Zarr level: the plugin's C++ OMEZarrReader against Debian's python3-zarr.

    pvbatch Testing/Benchmarks/benchmark_omezarr.py DIR [--repeat N]

DIR/brain.ome.zarr as mpi_omezarr_check.py --write writes it (e.g. --upsample 2 --chunk 64).
Times, best of N (default 3), in one pvbatch process:
  reader   OMEZarrReader, ResolutionLevel 0, the whole level (UpdatePipeline);
  python   zarr.open(level)[c] for each channel (numcodecs' Blosc), then numpy_to_vtk
           into a vtkImageData with one array per channel: what a Python reader in the
           plugin (VTKPythonAlgorithmBase) would do in its RequestData;
  python sub-extent / reader sub-extent: a quarter of z (what each of 4 MPI processes
           reads), zarr slicing vs UpdateExtent.
Prints the peak resident memory after each (ru_maxrss, which only grows) and whether the
two agree voxel for voxel.
"""
import argparse
import os
import resource
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

T.load_plugin({})
import numpy as np  # noqa: E402
import zarr  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("folder")
parser.add_argument("--repeat", type=int, default=3)
args = parser.parse_args()
folder = os.path.join(args.folder, "brain.ome.zarr")


def peak_gib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0 ** 2


def best(function):
    times = []
    result = None
    for _ in range(args.repeat):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), result


def with_reader(extent=None):
    reader = simple.OMEZarrReader(FileName=folder, ResolutionLevel=0)
    reader.UpdatePipelineInformation()
    algorithm = reader.GetClientSideObject()
    if extent is None:
        reader.UpdatePipeline()
    else:
        algorithm.UpdateExtent(extent)
    image = algorithm.GetOutputDataObject(0)
    values = [vtk_to_numpy(image.GetPointData().GetArray(i)).copy()
              for i in range(image.GetPointData().GetNumberOfArrays())]
    simple.Delete(reader)
    return values


def with_python(zslice=slice(None)):
    level = zarr.open(os.path.join(folder, "0"), mode="r")
    image = vtkImageData()
    nz, ny, nx = level.shape[1:]
    zs = range(nz)[zslice]
    image.SetExtent(0, nx - 1, 0, ny - 1, zs.start, zs.stop - 1)
    values = []
    for c in range(level.shape[0]):
        block = np.ascontiguousarray(level[c, zslice])
        array = numpy_to_vtk(block.ravel(), deep=1)
        array.SetName("C%d" % (c + 1))
        image.GetPointData().AddArray(array)
        values.append(block.ravel())
    return values


shape = zarr.open(os.path.join(folder, "0"), mode="r").shape
nz, ny, nx = shape[1:]
quarter = (0, nx - 1, 0, ny - 1, 0, nz // 4 - 1)
print("level 0: %s (c, z, y, x), chunks %s" % (shape, zarr.open(os.path.join(folder, "0")).chunks))
t_reader, a = best(with_reader)
print("reader whole level     %.3f s  peak %.2f GiB" % (t_reader, peak_gib()))
t_python, b = best(with_python)
print("python whole level     %.3f s  peak %.2f GiB" % (t_python, peak_gib()))
print("equal: %s" % all(np.array_equal(x, y) for x, y in zip(a, b)))
t_reader_q, a = best(lambda: with_reader(quarter))
t_python_q, b = best(lambda: with_python(slice(0, nz // 4)))
print("reader quarter of z    %.3f s" % t_reader_q)
print("python quarter of z    %.3f s" % t_python_q)
print("equal: %s" % all(np.array_equal(x, y) for x, y in zip(a, b)))
os._exit(0)
