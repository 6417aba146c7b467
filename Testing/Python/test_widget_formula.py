"""The Python helpers' copies of the Gaussian widgets' opacity formula and palette
(multichannel_explorer.picking._widget_alpha, probing.palette_color) against the C++ ones
(Filters/Core/transfer_function/GaussianWidgetFormula.h, as the core evaluates them):

* opacity: 40 random sets of 1 to 12 widgets (centres, sigmas over two decades, peak
  opacities, some beyond [0, 1] to be clamped) on 500 sampled points each of a volume whose
  coordinates are the voxel positions: ReducedDomain's WidgetOpacity (the C++ core) equals
  _widget_alpha at each point's coordinates within float rounding (|d| <= 2e-6);
* palette: the 16 colours of 16 seeded widgets (ReducedDomain's SeededWidgets, the core's
  widgetColor) equal palette_color(0..15).
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

C = T.Checker("test_widget_formula")
rng = random.Random(20261128)

wavelet = Wavelet(WholeExtent=[-20, 20, -20, 20, -20, 20])
coords = Calculator(Input=wavelet, Function="coords", ResultArrayName="ReducedCoordinates",
                    ResultArrayType="Float")


def random_widgets(count):
    flat = []
    for _ in range(count):
        centre = [rng.uniform(-20.0, 20.0) for _ in range(3)]
        sigma = 10 ** rng.uniform(-0.3, 1.3)
        colour = [rng.random() for _ in range(3)]
        opacity = rng.uniform(-0.2, 1.2)
        flat += centre + [sigma] + colour + [opacity]
    return flat


domain = simple.ReducedDomain(Input=coords, SampleSize=500, RandomSeed=1)
domain.Coordinates = ["POINTS", "ReducedCoordinates"]
worst, compared = 0.0, 0
for trial in range(40):
    widgets = random_widgets(rng.randint(1, 12))
    domain.GaussianWidgets = widgets
    domain.RandomSeed = trial + 1
    domain.UpdatePipeline()
    cloud = servermanager.Fetch(domain)
    opacity = cloud.GetPointData().GetArray("WidgetOpacity")
    for p in range(cloud.GetNumberOfPoints()):
        python = picking._widget_alpha(widgets, cloud.GetPoint(p))
        worst = max(worst, abs(python - opacity.GetValue(p)))
        compared += 1
C.check(compared == 40 * 500 and worst <= 2e-6,
        "Python's _widget_alpha equals the core's WidgetOpacity on %d random points of 40 random "
        "widget sets (largest difference %.2e)" % (compared, worst))

seeded = simple.ReducedDomain(Input=coords, SampleSize=5000, SeedWidgetCount=16, SkipLargestCluster=0)
seeded.Coordinates = ["POINTS", "ReducedCoordinates"]
seeded.UpdatePipeline()
seeded.UpdatePropertyInformation()
flat = [float(v) for v in seeded.GetProperty("SeededWidgets")]
colours = [flat[i + 4:i + 7] for i in range(0, len(flat), 8)]
C.check(len(colours) == 16 and all(
    max(abs(a - b) for a, b in zip(c, mce.palette_color(i))) <= 1e-6 for i, c in enumerate(colours)),
    "palette_color(0..15) equals the colours of 16 widgets the core seeded (%d seeded)" % len(colours))
C.finish()
