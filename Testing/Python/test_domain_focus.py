"""The reduced domain as a reader of it sees it (ReducedDomain's DisplayColor and
FocusBounds, show_dual_domain's framing), on a volume whose reduced coordinates are the voxel
positions (41^3 voxels in [-20, 20]^3) but for one far outlier, the corner voxel moved to
x = 1020:

* FocusBounds leaves the outlier out (x up to 20, not 1020), holds every other point, and
  is widened to the sphere (centre +- sigma) of a shown widget outside the cloud but not to a
  hidden one's;
* DisplayColor is the widget colour over grey (0.75) by how strongly the shown widgets select
  the point, 1 - prod(1 - w_i) with every shown widget at peak opacity 1 (Python's copy of
  the formula, picking._widget_alpha, with opacities 1): a faint widget (peak opacity 0.05)
  colours its centre fully; a point far from every widget stays grey;
* the hidden widget's sphere has diameter 0 (not drawn), the others 2 sigma;
* show_dual_domain frames the domain view on FocusBounds (its focal point is their
  centre), where Reset Camera fits the outlier too.
"""
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
from multichannel_explorer import picking  # noqa: E402

C = T.Checker("test_domain_focus")

wavelet = Wavelet(WholeExtent=[-20, 20, -20, 20, -20, 20])
coords = Calculator(Input=wavelet, ResultArrayName="ReducedCoordinates", ResultArrayType="Float",
                    Function="coords + 1000*(coordsX>19.5)*(coordsY>19.5)*(coordsZ>19.5)*iHat")

faint = [0.0, 0.0, 0.0, 3.0, 1.0, 0.0, 0.0, 0.05]        # red, peak opacity 0.05
outside = [40.0, 0.0, 0.0, 2.0, 0.0, 0.0, 1.0, 0.5]      # blue, beyond the cloud in x
hidden = [-60.0, 0.0, 0.0, 2.0, 0.0, 1.0, 0.0, 0.0]      # green, opacity 0: hidden
widgets = faint + outside + hidden

domain = simple.ReducedDomain(Input=coords, SampleSize=100000, GaussianWidgets=widgets)
domain.Coordinates = ["POINTS", "ReducedCoordinates"]
domain.UpdatePipeline()
cloud = servermanager.Fetch(domain)
focus = cloud.GetFieldData().GetArray("FocusBounds")
bounds = [focus.GetComponent(0, c) for c in range(6)] if focus else []
C.check(cloud.GetNumberOfPoints() == 41 ** 3,
        "every voxel is drawn (%d points)" % cloud.GetNumberOfPoints())
C.check(bounds == [-20.0, 42.0, -20.0, 20.0, -20.0, 20.0],
        "FocusBounds leaves out the outlier at x = 1020 and takes in the shown widget's sphere "
        "up to x = 42, not the hidden one at x = -60: %s" % bounds)

spheres = servermanager.Fetch(domain, None, None, 1)  # port 1: the widgets
diameters = [spheres.GetPointData().GetArray("Diameter").GetValue(i)
             for i in range(spheres.GetNumberOfPoints())]
C.check(diameters == [6.0, 4.0, 0.0],
        "the widgets' sphere diameters are 2 sigma, 0 for the hidden one: %s" % diameters)

colour = cloud.GetPointData().GetArray("DisplayColor")
selecting = list(widgets)
for i in range(0, len(selecting), 8):
    selecting[i + 7] = 1.0 if selecting[i + 7] > 0 else 0.0
rng = random.Random(20261129)
at = {cloud.GetPoint(p): p for p in range(cloud.GetNumberOfPoints())}
centre = colour.GetTuple3(at[(0.0, 0.0, 0.0)])
far = colour.GetTuple3(at[(-20.0, -20.0, -20.0)])
worst = 0
for p in rng.sample(range(cloud.GetNumberOfPoints()), 2000):
    x = cloud.GetPoint(p)
    if abs(x[0]) > 100:
        continue
    blend = picking._widget_alpha(selecting, x)
    # the point's colour: the alpha-weighted mean of the widget colours (only two are shown)
    a_faint = picking._widget_alpha(faint, x)
    a_out = picking._widget_alpha(outside, x)
    total = a_faint + a_out
    rgb = [(a_faint * faint[4 + k] + a_out * outside[4 + k]) / total if total > 0 else 0.0
           for k in range(3)]
    expect = [round(255 * (blend * rgb[k] + (1 - blend) * 0.75)) for k in range(3)]
    worst = max(worst, max(abs(a - b) for a, b in zip(colour.GetTuple3(p), expect)))
C.check(worst <= 1, "DisplayColor is the colour over grey by 1 - prod(1 - w_i) of the shown "
        "widgets at peak opacity 1 at 2000 random points (largest difference %d of 255)" % worst)
C.check(centre == (255.0, 0.0, 0.0) and far == (191.0, 191.0, 191.0),
        "the faint widget's centre is its full colour %s; a point far from every widget is grey %s"
        % (centre, far))

view = simple.CreateRenderView()
view.ViewSize = [400, 400]
display = mce.show_gaussian_tf(coords, view)
display.GaussianWidgets = widgets
dual = mce.show_dual_domain(display, view, sample_size=100000)
focal = list(dual.domain_view.CameraFocalPoint)
expect = [(bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3)] if bounds else []
C.check(len(expect) == 3 and max(abs(f - e) for f, e in zip(focal, expect)) <= 1e-6,
        "show_dual_domain frames the domain view on FocusBounds: focal point %s, their centre %s"
        % (focal, expect))
simple.ResetCamera(dual.domain_view)
simple.Render(dual.domain_view)
C.check(dual.domain_view.CameraFocalPoint[0] > 400,
        "Reset Camera fits the outlier too (focal point x %.1f)" % dual.domain_view.CameraFocalPoint[0])
C.finish()
