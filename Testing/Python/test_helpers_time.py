"""The helpers work at the time step on screen: a series whose every step has its own known
best view.

Known answer: three time steps (a .vti file each, opened as one series), each five Gaussian
blobs on a plane through the grid's centre with its own normal (x+2y+2z, 2x-y+z/2, y-z);
the interest points are the blobs, so the best view of step t is its plane's normal.
- apply_best_viewpoint(volume, view) with the view at step t looks along +-normal(t), also
  when its BestViewpoint filter was last updated at another step (a filter's UpdatePipeline()
  without a time re-runs at the time last asked of it, not at the view's);
- best_viewpoint_filter(volume, view) gives step t's direction; with no view, the active
  view's step;
- probe(volume, voxel) at step t reads that step's value (a voxel on a blob of one step
  only), in any order of steps.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_helpers_time")
out = os.path.join(T.output_dir(), "helpers_time")
os.makedirs(out, exist_ok=True)
N = 48
NORMALS = [T.unit(n) for n in ([1.0, 2.0, 2.0], [2.0, -1.0, 0.5], [0.0, 1.0, -1.0])]


def blobs_on_plane(normal):
    """Five Gaussian blobs (sigma 2.5 voxels) on the plane through the centre with this
    normal: the centre and +-12 voxels along two in-plane axes."""
    u = T.unit(np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0]))
    w = np.cross(normal, u)
    z, y, x = np.mgrid[0:N, 0:N, 0:N].astype(np.float64)
    c = (N - 1) / 2.0
    volume = np.zeros((N, N, N))
    u, w = np.array(u), np.array(w)
    for center in [np.zeros(3)] + [s * 12.0 * a for a in (u, w) for s in (-1.0, 1.0)]:
        px, py, pz = c + center
        volume += np.exp(-((x - px) ** 2 + (y - py) ** 2 + (z - pz) ** 2) / (2 * 2.5 ** 2))
    return volume


files, volumes = [], []
for step, normal in enumerate(NORMALS):
    image = vtkImageData()
    image.SetDimensions(N, N, N)
    volumes.append(blobs_on_plane(np.array(normal)).astype(np.float32))  # [z, y, x]
    values = numpy_to_vtk(np.ascontiguousarray(volumes[-1]).ravel(), deep=True)
    values.SetName("blobs")
    image.GetPointData().SetScalars(values)
    files.append(os.path.join(out, "blobs_%d.vti" % step))
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(files[-1])
    writer.SetInputData(image)
    writer.Write()

series, times, scene = T.open_series(files, C)
view = T.render_view([300, 300])
display = simple.Show(series, view)
display.SetRepresentationType("Volume")
simple.ColorBy(display, ("POINTS", "blobs"))


def angle_to(direction, normal):
    cosine = abs(sum(a * b for a, b in zip(direction, normal)))
    return math.degrees(math.acos(min(1.0, cosine)))


def at(step):
    scene.AnimationTime = times[step]
    view.ViewTime = times[step]
    simple.Render(view)


# Steps in an order that leaves the filter at another step each time.
for step in (0, 2, 1, 0):
    at(step)
    result = mce.apply_best_viewpoint(series, view)
    C.check(result.valid and angle_to(result.direction, NORMALS[step]) < 3.0,
            "view at step %d: apply_best_viewpoint looks along its plane's normal (%.2f deg; "
            "the other steps' normals %s deg)" % (
                step, angle_to(result.direction, NORMALS[step]),
                ["%.0f" % angle_to(result.direction, n) for k, n in enumerate(NORMALS)
                 if k != step]))
at(2)
simple.SetActiveView(view)
for name, bvp in (("best_viewpoint_filter(volume, view)", mce.best_viewpoint_filter(series, view)),
                  ("best_viewpoint_filter(volume), the active view",
                   mce.best_viewpoint_filter(series))):
    direction = [float(v) for v in bvp.GetPropertyValue("BestViewDirection")]
    C.check(angle_to(direction, NORMALS[2]) < 3.0,
            "%s at step 2: its plane's normal (%.2f deg)" % (name, angle_to(direction, NORMALS[2])))

# A voxel where the steps differ most: on a blob of one step, off the others'. probe needs
# reduced coordinates: 0.1 x the position, every step.
reduced = simple.Calculator(Input=series, Function="0.1*coords",
                            ResultArrayName="ReducedCoordinates", ResultArrayType="Float")
spread = np.max(volumes, axis=0) - np.min(volumes, axis=0)
k, j, i = [int(v) for v in np.unravel_index(int(np.argmax(spread)), spread.shape)]
for step in (1, 0, 2, 1):
    at(step)
    hit = mce.probe(reduced, (i, j, k), view=view, mark=False)
    value = hit["values"]["blobs"]
    got = float(value[0] if isinstance(value, (list, tuple)) else value)
    want = float(volumes[step][k, j, i])
    C.check(abs(got - want) < 1e-6,
            "view at step %d: probe of voxel (%d, %d, %d) reads its value %.4f (got %.4f; the "
            "steps' values %s)" % (step, i, j, k, want, got,
                                   ["%.3f" % float(v[k, j, i]) for v in volumes]))
C.finish()
