"""Examples/best_viewpoint.py on the real diffusion MRI volume (dipy's small_64D.nii: 10 x 10 x
10 voxels of 65 components, read with TimeAsVector), with --output as the other examples
spell it.

Known answers:
- a volume of several components is shown and analysed by one array, its magnitude (the
  picture ParaView draws of a vector array), and the script says so;
- every picture is framed: the volume, whose best view was found for the opacity drawn,
  keeps off the picture's edges (before, the view was fitted to the voxels of the first
  component's opacity while the picture showed the magnitude's: worst.png ran off three
  edges);
- the camera's view-up is v2 signed towards the positive side of the axis it lies closest
  to (upright).
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_best_viewpoint_example")
import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

out = os.path.join(T.output_dir(), "best_viewpoint_4d")
plugin = ["--plugin", os.environ["MCV_PLUGIN"]] if os.environ.get("MCV_PLUGIN") else []
run = T.run_pvbatch("pvbatch", [os.path.join(T.REPO, "Examples", "best_viewpoint.py"),
                                T.data_file("small_64D.nii"), "--output", out,
                                "--size", "400", "300"] + plugin)
print(run.stdout[-1500:])
C.check(run.returncode == 0 and "65 components per voxel: shown and analysed by their "
        "magnitude 'small_64D_magnitude'" in run.stdout,
        "best_viewpoint.py --output on a 65-component volume: exit %d, by its magnitude"
        % run.returncode)

for name in ("best", "best_points", "worst"):
    path = os.path.join(out, name + ".png")
    if not C.check(os.path.exists(path), "%s.png written" % name):
        continue
    image = mce._read_png(path)
    w, h, _ = image.GetDimensions()
    rgb = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].astype(int)
    background = rgb[0, 0]
    drawn = np.abs(rgb - background).max(axis=2) > 8
    drawn[: h // 5, : w // 5] = False  # the orientation axes' corner (rows from the bottom)
    edges = {"bottom": int(drawn[0].sum()), "top": int(drawn[-1].sum()),
             "left": int(drawn[:, 0].sum()), "right": int(drawn[:, -1].sum())}
    C.check(drawn.mean() > 0.02 and not any(edges.values()),
            "%s.png: the volume drawn (%.1f %% of the pixels) and off every edge %s"
            % (name, 100 * drawn.mean(), edges))

report = os.path.join(out, "best_viewpoint.json")
if C.check(os.path.exists(report), "best_viewpoint.json written"):
    with open(report) as f:
        summary = json.load(f)
    up = summary["view_up"]
    leading = max((2, 1, 0), key=lambda a: abs(up[a]))
    C.check(up[leading] > 0, "view-up %s points to +%s, the axis it lies closest to (upright)"
            % (up, "xyz"[leading]))
C.finish()
