"""The 3-channel brain read from OME-Zarr through the method's chain (multichannel_explorer:
DimensionReduction, show_gaussian_tf, auto_widgets, apply_best_viewpoint), against the
same chain on the NIfTI files subsampled onto the same grid.

The image is written with level 1 = every second voxel of the source, spacing 2, origin 0:
exactly the grid of ExtractSubset (rate 2) of the NIfTI channels, so the reduced
coordinates must be the same and the best view the same direction. Writes
omezarr_chain/best.png (the OME-Zarr brain through its widgets, from its best view).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

mce = T.load_plugin({})
import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

import omezarr_testing as Z  # noqa: E402

C = T.Checker("test_omezarr_chain")
OUT = T.fresh_output_dir("omezarr_chain")

brain = Z.brain_arrays()
folder = Z.write_image(os.path.join(OUT, "brain.ome.zarr"),
                       [brain, brain[:, ::2, ::2, ::2]],
                       scales=[[1, 1, 1, 1], [1, 2, 2, 2]], chunks=(1, 48, 48, 48))
zarr_volume = simple.OpenDataFile(folder)
zarr_volume.ResolutionLevel = 1
nifti_volume = simple.ExtractSubset(Input=T.brain_channels(), VOI=[0, 180, 0, 216, 0, 180],
                                    SampleRateI=2, SampleRateJ=2, SampleRateK=2)

REDUCTION = dict(FeatureSet="6D", Method="PCA", OutputDimension=3,
                 ReferenceSampleSize=5000, RandomSeed=7)


def chain(volume, name):
    reduction = simple.DimensionReduction(Input=volume, **REDUCTION)
    reduction.UpdatePipeline()
    view = simple.CreateView("RenderView")
    view.ViewSize = [480, 400]
    view.OrientationAxesVisibility = 1
    display = mce.show_gaussian_tf(reduction, view)
    mce.auto_widgets(display, 3, seed=7)
    view.ResetCamera()
    best = mce.apply_best_viewpoint(reduction, view, disambiguate=True)
    simple.Render(view)
    path = os.path.join(OUT, name + ".png")
    simple.SaveScreenshot(path, view)
    data = servermanager.Fetch(reduction)
    coords = vtk_to_numpy(data.GetPointData().GetArray("ReducedCoordinates"))
    return data, coords, best, path


zarr_data, zarr_coords, zarr_best, zarr_png = chain(zarr_volume, "best")
nifti_data, nifti_coords, nifti_best, nifti_png = chain(nifti_volume, "best_nifti")

C.check(zarr_data.GetDimensions() == nifti_data.GetDimensions() == (91, 109, 91) and
        zarr_data.GetSpacing() == nifti_data.GetSpacing() == (2.0, 2.0, 2.0),
        "the OME-Zarr level 1 and the subsampled NIfTI channels are one grid: %s %s, %s %s"
        % (zarr_data.GetDimensions(), zarr_data.GetSpacing(), nifti_data.GetDimensions(),
           nifti_data.GetSpacing()))
names = [zarr_data.GetPointData().GetArrayName(i) for i in range(3)]
C.check(names == Z.LABELS, "the channels keep their omero names down the chain: %s" % names)
C.check(zarr_coords.shape == nifti_coords.shape and np.array_equal(zarr_coords, nifti_coords),
        "reduced coordinates of every voxel equal those of the NIfTI channels (%s, largest "
        "difference %s)" % (zarr_coords.shape, np.abs(zarr_coords - nifti_coords).max()
                            if zarr_coords.shape == nifti_coords.shape else "n/a"))
C.check(zarr_best.valid and nifti_best.valid and
        T.angle_deg(zarr_best.direction, nifti_best.direction) < 0.5,
        "best view from OME-Zarr %s = from NIfTI %s" % (list(zarr_best.direction),
                                                        list(nifti_best.direction)))
stats = mce.image_statistics(zarr_png)
C.check(stats["non_background_fraction"] > 0.05,
        "the picture shows the brain: %.1f %% of %s's pixels are not background"
        % (100 * stats["non_background_fraction"], zarr_png))
C.finish()
