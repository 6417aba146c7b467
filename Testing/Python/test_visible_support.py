"""What the best-view picture shows and the camera fitted to it, on an ellipsoid of
opaque voxels (semi-axes 12, 7, 4 about (5, -3, 2) in a 41^3 grid of spacing 1 around the
origin; opacity 1 inside, 0 outside):

* BestViewpoint's VisibleBounds are the ellipsoid's voxel bounds (x -7..17, y -10..4,
  z -2..6);
* VisibleSupport: for each of its 128 directions, the point is an ellipsoid voxel and no
  ellipsoid voxel lies further along the direction (every voxel checked here); the
  directions cover the sphere (the six axes among them);
* apply_best_viewpoint fits the camera to them: every support point projects inside the
  view, and the furthest at 1 / 1.15 of the half-width or half-height (the 15 % margin),
  within a pixel; with parallel projection too.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
import gaussian_tf_testing as G  # noqa: E402

C = T.Checker("test_visible_support")
CENTRE, AXES = (5.0, -3.0, 2.0), (12.0, 7.0, 4.0)


def inside(p):
    return sum(((p[a] - CENTRE[a]) / AXES[a]) ** 2 for a in range(3)) <= 1.0


wavelet = Wavelet(WholeExtent=[-20, 20, -20, 20, -20, 20])
ellipsoid = Calculator(Input=wavelet, ResultArrayName="inside", Function=(
    "((coordsX-5)^2/144 + (coordsY+3)^2/49 + (coordsZ-2)^2/16 <= 1)*1.0"))
ramp = simple.CreatePiecewiseFunction(Points=[0.0, 0.0, 0.5, 0.0, 1.0, 1.0, 0.5, 0.0])
bvp = mce.best_viewpoint_filter(ellipsoid, None, Channels=["inside"], OpacityFunction=ramp)
bounds = [float(v) for v in bvp.GetPropertyValue("VisibleBounds")]
C.check(bounds == [-7.0, 17.0, -10.0, 4.0, -2.0, 6.0],
        "VisibleBounds are the ellipsoid's voxel bounds: %s" % bounds)

flat = [float(v) for v in bvp.GetProperty("VisibleSupport")]
support = [flat[i:i + 3] for i in range(0, len(flat), 3)]
voxels = [(x, y, z) for z in range(-20, 21) for y in range(-20, 21) for x in range(-20, 21)
          if inside((x, y, z))]
directions = T.support_directions()
worst = 0.0
for p, d in zip(support, directions):
    best = max(sum(v[a] * d[a] for a in range(3)) for v in voxels)
    worst = max(worst, best - sum(p[a] * d[a] for a in range(3)))
C.check(len(support) == 128 and all(inside(p) for p in support) and worst <= 1e-9,
        "the 128 support points are ellipsoid voxels, each the furthest along its direction "
        "(%d points, %d voxels checked, largest shortfall %.1e)" % (len(support), len(voxels), worst))

for parallel in (0, 1):
    view = simple.CreateRenderView()
    view.ViewSize = [400, 300]
    view.CameraParallelProjection = parallel
    simple.Show(ellipsoid, view)
    result = mce.apply_best_viewpoint(ellipsoid, view, Channels=["inside"], OpacityFunction=ramp)
    simple.Render(view)
    reach = 0.0
    for p in support:
        x, y = G.project(view, p)
        reach = max(reach, abs(x - 199.5) / 200.0, abs(y - 149.5) / 150.0)
    C.check(result.valid and abs(reach - 1 / 1.15) <= 1.5 / 150.0,
            "%s: every support point is in view, the furthest at %.3f of the half-size "
            "(1 / 1.15 = %.3f)" % ("parallel" if parallel else "perspective", reach, 1 / 1.15))
    simple.Delete(view)
C.finish()
