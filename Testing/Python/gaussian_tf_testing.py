"""Helpers of the "Gaussian TF Volume" pvbatch tests: a black render view with a known
camera, pixels of a screenshot at the projection of a world point, the representation's
read-back information and its VTK messages."""

import os

import mcv_testing as T


def coords_2d(source, n):
    """A ProgrammableFilter on source (an n^3 image at unit spacing from the origin) that adds
    the 2-component float array "Coords2D" = (x, y) / (n - 1), so [0,1]^2."""
    from paraview import simple
    two_d = simple.ProgrammableFilter(Input=source)
    two_d.Script = """
from vtkmodules.vtkCommonCore import vtkFloatArray
inp = self.GetInput()
out = self.GetOutput()
out.ShallowCopy(inp)
a = vtkFloatArray()
a.SetName("Coords2D")
a.SetNumberOfComponents(2)
n = inp.GetNumberOfPoints()
a.SetNumberOfTuples(n)
for i in range(n):
    p = inp.GetPoint(i)
    a.SetTuple2(i, p[0] / %d.0, p[1] / %d.0)
out.GetPointData().AddArray(a)
""" % (n - 1, n - 1)
    return two_d


def print_mode_table(rows, quantity, extra_headers, extra_cells):
    """Prints a Markdown table of a Gaussian TF benchmark, one line per volume. Each row holds
    "voxels" and, for "Per sample" and "Per voxel", a tuple whose first value is `quantity` in
    seconds; the table gives both, their ratio, then the columns extra_headers whose cells
    extra_cells(per_sample, per_voxel) returns as strings."""
    print("\n| voxels | per sample: %s | per voxel: %s | per voxel / per sample | %s |"
          % (quantity, quantity, " | ".join(extra_headers)))
    print("|---" * (4 + len(extra_headers)) + "|")
    for row in rows:
        s, v = row["Per sample"], row["Per voxel"]
        print("| %.1f M | %.3f ms | %.1f ms | %.0fx | %s |"
              % (row["voxels"] / 1e6, 1e3 * s[0], 1e3 * v[0], v[0] / max(s[0], 1e-9),
                 " | ".join(extra_cells(s, v))))


def black_view(size=(400, 400)):
    return T.render_view(size)


def look_down_z(view, bounds):
    """Parallel projection along -z onto the xy plane of `bounds`."""
    from paraview import simple

    simple.Render(view)  # the first render resets the camera: set ours after it
    c = [(bounds[2 * i] + bounds[2 * i + 1]) / 2.0 for i in range(3)]
    view.CameraFocalPoint = c
    view.CameraPosition = [c[0], c[1], c[2] + 4 * (bounds[5] - bounds[4] + 1)]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = 0.6 * max(bounds[1] - bounds[0], bounds[3] - bounds[2])
    simple.Render(view)


def project(view, point):
    """Display (x, y) pixel of a world point, origin at the bottom left."""
    ren = view.GetRenderer()
    ren.SetWorldPoint(point[0], point[1], point[2], 1.0)
    ren.WorldToDisplay()
    x, y, _ = ren.GetDisplayPoint()
    return int(round(x)), int(round(y))


class Shot(object):
    """A screenshot read back with vtkPNGReader (rows bottom-up, like display pixels)."""

    def __init__(self, view, path):
        from paraview import simple
        from vtkmodules.vtkIOImage import vtkPNGReader

        size = [int(v) for v in view.ViewSize]
        simple.SaveScreenshot(path, view, ImageResolution=size)
        reader = vtkPNGReader()
        reader.SetFileName(path)
        reader.Update()
        self.path = path
        self.image = reader.GetOutput()
        self.scalars = self.image.GetPointData().GetScalars()
        self.size = self.image.GetDimensions()[:2]

    def rgb(self, xy):
        x = min(max(xy[0], 0), self.size[0] - 1)
        y = min(max(xy[1], 0), self.size[1] - 1)
        return [int(v) for v in self.scalars.GetTuple(self.image.ComputePointId([x, y, 0]))[:3]]

    def max_channel(self):
        return max(self.scalars.GetRange(c)[1] for c in range(3))


def difference(a, b, brightness=False):
    """Two Shots of one size: (largest channel difference, share of pixels whose channels
    differ by more than 2 of 255). With `brightness`, the largest difference is that of
    each pixel's brightest channel."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    x = vtk_to_numpy(a.scalars)[:, :3].astype(np.int32)
    y = vtk_to_numpy(b.scalars)[:, :3].astype(np.int32)
    d = np.abs(x - y).max(axis=1)
    largest = np.abs(x.max(axis=1) - y.max(axis=1)).max() if brightness else d.max()
    return int(largest), float((d > 2).mean())


def skipping_unchanged(checker, view, display, label, path_stem, maximum_intensity=False):
    """Renders `display` with EmptySpaceSkipping on and off and checks that the pictures
    agree (no channel more than 8/255 apart, at most 0.1 % of the pixels more than 2/255);
    returns the information of the render with skipping; leaves skipping off (the
    un-culled loop). With `maximum_intensity`, the
    brightness of each pixel is compared instead of its channels: a ray whose two most
    opaque samples (of different widgets) tie within 1e-6 takes either one's colour."""
    from paraview import simple

    display.EmptySpaceSkipping = 1
    simple.Render(view)
    on = Shot(view, output_path(path_stem + "_skipping.png"))
    state = info(display)
    display.EmptySpaceSkipping = 0
    simple.Render(view)
    off = Shot(view, output_path(path_stem + "_no_skipping.png"))
    simple.Render(view)
    largest, share = difference(on, off, brightness=maximum_intensity)
    print("%s: skipping vs not: largest difference %d/255, %.4f %% of pixels > 2/255; "
          "bricks %s" % (label, largest, 100 * share, state.get("bricks")))
    checker.check(on.max_channel() > 30, "%s: something is drawn with skipping" % label)
    checker.check(largest <= 8 and share <= 0.001,
                  "%s: the same picture with and without empty space skipping (largest "
                  "difference %d/255, %.4f %% of pixels > 2/255)" % (label, largest, 100 * share))
    return state


def info(display):
    """What the representation's last render computed (information-only properties)."""
    display.UpdatePropertyInformation()
    return {
        "computations": int(display.GetPropertyValue("GaussianTFComputations")),
        "data_updates": int(display.GetPropertyValue("GaussianTFDataUpdates")),
        "valid": int(display.GetPropertyValue("GaussianTFValid")),
        "device": str(display.GetPropertyValue("GaussianTFDeviceUsed")),
        "texture_builds": int(display.GetPropertyValue("GaussianTFTextureBuilds")),
        "preparation_s": float(display.GetPropertyValue("GaussianTFPreparationSeconds")),
        "skipping_used": int(display.GetPropertyValue("GaussianTFSkippingUsed")),
        "bricks": (int(display.GetPropertyValue("GaussianTFBricks")),
                   int(display.GetPropertyValue("GaussianTFEmptyBricks")),
                   float(display.GetPropertyValue("GaussianTFWidgetsPerBrick"))),
    }


def messages(display):
    """Errors/warnings of the representation's VTK object (its active subrepresentation,
    the vtkGaussianTFVolumeRepresentation, in pvbatch's built-in session)."""
    return T.Messages(display.GetClientSideObject().GetActiveRepresentation())


def is_colour(rgb, channel, min_value, max_other_fraction=0.1):
    """rgb is dominated by `channel` (0 red, 1 green, 2 blue)."""
    main = rgb[channel]
    others = [v for i, v in enumerate(rgb) if i != channel]
    return main >= min_value and all(o <= max_other_fraction * main for o in others)


def output_path(name):
    return os.path.join(T.output_dir(), name)
