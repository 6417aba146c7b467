"""BestViewpoint's NumberOfNonFiniteVoxels counts every NaN/Inf voxel of the volume once,
in one process and split over several (ghost layers and the faces that neighbouring pieces
share are not counted twice).

  pvbatch mpi_nonfinite_check.py                       one process
  mpiexec -np R pvbatch --mpi mpi_nonfinite_check.py   R processes

The volume is synthetic (the count is the point): a 40 x 30 x 20 float32 ramp written as a
raw file, with NaN and +/-Inf at voxels spread over the whole volume, so every piece and
every piece boundary holds some. Test driver: test_mpi.sh.
"""
import array
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

DIMS = (40, 30, 20)


def write_volume(path):
    """The raw file and how many of its voxels are not finite."""
    values = array.array("f")
    bad = 0
    for k in range(DIMS[2]):
        for j in range(DIMS[1]):
            for i in range(DIMS[0]):
                key = (7 * i + 3 * j + 11 * k) % 41
                if key == 0:
                    values.append(math.nan)
                elif key == 1:
                    values.append(math.inf if (i + j + k) % 2 else -math.inf)
                else:
                    values.append(float(i + j + k))
                    continue
                bad += 1
    if sys.byteorder != "little":
        values.byteswap()
    with open(path, "wb") as f:
        values.tofile(f)
    return bad


def main():
    mce = T.load_plugin(globals())
    from paraview.simple import BestViewpoint
    pm = servermanager.vtkProcessModule.GetProcessModule()
    R = pm.GetNumberOfLocalPartitions()
    C = T.Checker("mpi_nonfinite_check (%d process%s)" % (R, "es" if R > 1 else ""))

    path = os.path.join(T.output_dir(), "nonfinite_%d.raw" % R)
    expected = write_volume(path)
    reader = simple.ImageReader(FileNames=[path])
    reader.DataScalarType = "float"
    reader.DataByteOrder = "LittleEndian"
    reader.FileDimensionality = 3
    reader.DataExtent = [0, DIMS[0] - 1, 0, DIMS[1] - 1, 0, DIMS[2] - 1]
    reader.NumberOfScalarComponents = 1
    view = BestViewpoint(Input=reader)
    view.NumberOfInterestPoints = 256
    messages = T.Messages(view)
    view.UpdatePipeline()
    view.UpdatePropertyInformation()
    found = int(view.GetPropertyValue("NumberOfNonFiniteVoxels"))
    C.check(found == expected, "NumberOfNonFiniteVoxels = %d, the volume holds %d" % (found, expected))
    C.check(messages.any_warning("NaN/Inf"), "a warning names the NaN/Inf voxels")
    os.remove(path)
    C.finish_parallel()


if __name__ == "__main__":
    main()
