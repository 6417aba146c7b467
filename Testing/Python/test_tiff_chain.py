"""The whole chain on an ImageJ hyperstack equals the chain on the same channels as NIfTI files.

The real brain (Colin27 ch2, AAL, Brodmann) on a 2 mm grid (every second voxel, uint16) is
written twice: as one ImageJ hyperstack (tifffile, axes ZCYX, 2 um spacing) and as three
NIfTI files (vtkNIFTIImageWriter, spacing 2). The hyperstack is read by the checked TIFF
reader (channels C1..C3), the NIfTI files by the plugin's NIfTI reader and merged with
MergeChannels. On both: DimensionReduction (reduce_multichannel, 6D features, Isomap),
the Gaussian TF Volume with widgets seeded by auto_widgets, BestViewpoint
(apply_best_viewpoint) and a screenshot. Checked: the reduced coordinates are equal voxel
for voxel, the seeded widgets, best view directions and cameras equal, and the two
screenshots equal pixel for pixel (and not empty).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

import numpy as np  # noqa: E402
import tifffile  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.vtkIOImage import vtkNIFTIImageWriter  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_tiff_chain")
OUT = T.fresh_output_dir("tiff_chain")
NAMES = T.BRAIN


channels = list(T.brain_arrays(NAMES, step=2).astype(np.uint16))
Z, Y, X = channels[0].shape

hyperstack = os.path.join(OUT, "brain_zcyx.tif")
tifffile.imwrite(hyperstack, np.ascontiguousarray(np.stack(channels).transpose(1, 0, 2, 3)),
                 imagej=True, resolution=(1 / 2.0, 1 / 2.0),
                 metadata={"axes": "ZCYX", "spacing": 2.0, "unit": "um"})
nifti = []
for n, values in zip(NAMES, channels):
    image = vtkImageData()
    image.SetDimensions(X, Y, Z)
    image.SetSpacing(2.0, 2.0, 2.0)
    array = numpy_to_vtk(values.ravel(), deep=1)
    array.SetName(n)
    image.GetPointData().SetScalars(array)
    writer = vtkNIFTIImageWriter()
    writer.SetInputData(image)
    writer.SetFileName(os.path.join(OUT, n + "_2mm.nii"))
    writer.Write()
    nifti.append(writer.GetFileName())

tiff_source = simple.OpenDataFile(hyperstack)
nifti_source = simple.MergeChannels(Input=[simple.OpenDataFile(f) for f in nifti])
C.check(tiff_source.GetXMLName() == "CheckedTIFFReader", "the hyperstack opens with the "
        "checked TIFF reader (%s)" % tiff_source.GetXMLName())


def chain(source, label):
    source.UpdatePipeline()
    data = servermanager.Fetch(source, 0)
    names = [data.GetPointData().GetArrayName(i)
             for i in range(data.GetPointData().GetNumberOfArrays())]
    print("%s: arrays %s, dimensions %s, spacing %s"
          % (label, names, data.GetDimensions(), data.GetSpacing()))
    feats, reduction = mce.reduce_multichannel(
        source, "Isomap", "6D", output_dimension=3, ReferenceSampleSize=2000,
        NumberOfNeighbors=12, NumberOfLandmarks=200, RandomSeed=3)
    feats.Channels = names
    reduction.UpdatePipeline()
    result = servermanager.Fetch(reduction, 0)
    coords = vtk_to_numpy(result.GetPointData().GetArray("ReducedCoordinates")).copy()
    view = G.black_view((500, 500))
    display = mce.show_gaussian_tf(reduction, view)
    widgets = mce.auto_widgets(display, 3, seed=0)
    # The volumes' pixels only: the legend names the widgets after the channels, which
    # are named differently in the two files (C1.. against ch2..).
    display.ShowWidgetLegend = 0
    best = mce.apply_best_viewpoint(reduction, view)
    simple.Render(view)
    shot = G.Shot(view, os.path.join(OUT, "chain_%s.png" % label))
    pixels = vtk_to_numpy(shot.scalars).copy()
    state = G.info(display)
    return dict(names=names, dims=data.GetDimensions(), spacing=data.GetSpacing(),
                coords=coords, widgets=widgets, best=list(best.direction),
                valid=best.valid, camera=[list(view.CameraPosition), list(view.CameraViewUp)],
                pixels=pixels, path=shot.path, rendered=state["valid"])


a = chain(tiff_source, "hyperstack")
b = chain(nifti_source, "nifti")
C.check(a["names"] == ["C1", "C2", "C3"] and len(b["names"]) == 3,
        "channels: hyperstack %s, merged NIfTI %s" % (a["names"], b["names"]))
C.check(a["dims"] == b["dims"] == (X, Y, Z) and a["spacing"] == b["spacing"] == (2.0, 2.0, 2.0),
        "same grid: %s %s / %s %s" % (a["dims"], a["spacing"], b["dims"], b["spacing"]))
C.check(np.array_equal(a["coords"], b["coords"]),
        "ReducedCoordinates equal on every voxel (max difference %.3g)"
        % float(np.abs(a["coords"] - b["coords"]).max()))
C.check(a["widgets"] == b["widgets"] and len(a["widgets"]) == 24,
        "auto_widgets seeds the same 3 widgets: %s" % a["widgets"][:8])
C.check(a["valid"] and b["valid"] and a["best"] == b["best"] and a["camera"] == b["camera"],
        "best viewpoint equal: %s / %s" % (a["best"], b["best"]))
lit = int((a["pixels"][:, :3].max(axis=1) > 30).sum())
C.check(a["rendered"] == 1 and b["rendered"] == 1 and lit > 5000,
        "both rendered, %d lit pixels in %s" % (lit, a["path"]))
C.check(np.array_equal(a["pixels"], b["pixels"]),
        "the two screenshots are equal pixel for pixel (%d pixels differ): %s, %s"
        % (int((a["pixels"] != b["pixels"]).any(axis=1).sum()), a["path"], b["path"]))
C.finish()
