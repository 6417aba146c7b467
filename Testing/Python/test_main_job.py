"""(h) The main job (Examples/transfer_function.py) on the real 3-channel brain, small
settings (6D features, a 2000-voxel reference sample): features -> Isomap (the fused
DimensionReduction on the channels, the default chain) -> seeded widgets -> Gaussian TF
Volume -> best viewpoint of the widgets' opacity.

Checks model.mcvmodel and transfer_function.mcvtf (written beside the pictures, listed in
the report, they load: the seeded widgets exactly, the model's method and channels; applied
to the job's own channels, no voxel is out of the model), the report (every stage timed with its peak resident memory, finite trustworthiness and variance retained, a
valid best direction perpendicular to the worst one), that every image is written and
not blank, that the best-view image shows the seeded widgets' colours: pixels whose
colour is near a widget's hue, for at least two widgets; that spectrum.png has its bars
(along the row just above the axis: as many runs of the kept bars' colour as eigenvalues
kept, of the other colour as the others shown) and that methods.png has four panels of
points, widget-coloured and grey; and that nothing glows around the head: every pixel of
best.png outside the silhouette of the brain's foreground voxels (re-rendered here with
best.png's camera as the Foreground = 0.5 surface, dilated by 4 pixels) is the view's
background colour.
"""
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_main_job")
out = os.path.join(T.output_dir(), "main_job")
for name in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"):
    T.data_file(name)

command = [sys.executable if os.path.basename(sys.executable).startswith("pv") else "pvbatch",
           os.path.join(T.REPO, "Examples", "transfer_function.py"),
           "--features", "6D", "--reference-size", "2000", "--landmarks", "200",
           "--widgets", "3", "--size", "480", "360", "--output", out]
if os.environ.get("MCV_PLUGIN"):
    command += ["--plugin", os.environ["MCV_PLUGIN"]]
# Under its own X server through run_pvbatch.sh, which retries a lost X server as it does
# for every test (a nested pvbatch on this test's display had no such retry).
run = subprocess.run(["sh", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                         "run_pvbatch.sh"), "pvbatch"] + command[1:],
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
print(run.stdout[-3000:])
C.check(run.returncode == 0, "Examples/transfer_function.py ran (exit %d)" % run.returncode)
C.check("output: " in run.stdout, "it printed the output folder")

report_path = os.path.join(out, "report.json")
if not C.check(os.path.exists(report_path), "report.json written"):
    C.finish()
with open(report_path) as f:
    report = json.load(f)
# The default chain is the fused one: the features are computed inside the reduction stage.
C.check(report["chain"] == "fused" and "features" not in report["stage_seconds"] and
        set(report["stage_seconds"]) >= {"read", "reduction", "seed widgets",
                                         "best viewpoint", "dual domain", "methods"},
        "report: every stage timed %s" % sorted(report["stage_seconds"]))
C.check(set(report["stage_peak_rss_gib"]) == set(report["stage_seconds"]) and
        0 < report["peak_rss_gib"] < 64 and
        max(report["stage_peak_rss_gib"].values()) <= report["peak_rss_gib"],
        "report: peak resident memory %.2f GiB, per stage %s"
        % (report["peak_rss_gib"], report["stage_peak_rss_gib"]))
C.check(0.0 < report["variance_retained"] <= 1.0 and 0.5 < report["trustworthiness"] <= 1.0,
        "report: variance retained %.3f, trustworthiness %.3f"
        % (report["variance_retained"], report["trustworthiness"]))
best, worst = report["best_direction"], report["worst_direction"]
C.check(abs(T.norm(best) - 1) < 1e-6 and abs(T.dot(best, worst)) < 1e-6,
        "report: unit best direction perpendicular to the worst")
C.check(len(report["widgets"]) == 3, "report: 3 widgets seeded")

for name in ("best", "worst", "dual_domain", "domain", "spectrum", "methods"):
    T.image_ok(mce, os.path.join(out, name + ".png"), C, name, min_stddev=4.0,
               min_fraction=0.02)
C.check(set(report["images"]) >= {"spectrum", "methods"},
        "report: spectrum.png and methods.png listed")


def rgb_pixels(path):
    """The picture as a numpy array [row, column, rgb] (rows bottom to top)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    image = mce._read_png(path)
    width, height = image.GetDimensions()[:2]
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, -1)[:, :, :3]


def runs(mask):
    """Number of runs of True in a 1D boolean array (separate bars along a row)."""
    return int((mask[1:] & ~mask[:-1]).sum() + (1 if mask[0] else 0))


def bar_counts(path, kept_colour, other_colour):
    """Bars of each colour along the row with the most bar pixels (just above the axis,
    where every bar is; the legend's patches are higher up)."""
    import numpy

    pixels = rgb_pixels(path).astype(int)
    kept = (abs(pixels - numpy.array(kept_colour)).max(axis=2) <= 3)
    other = (abs(pixels - numpy.array(other_colour)).max(axis=2) <= 3)
    row = int((kept | other).sum(axis=1).argmax())
    return runs(kept[row]), runs(other[row]), int(kept.sum() + other.sum())


# spectrum.png: a bar per eigenvalue shown, the kept ones in their own colour.
figure = report.get("spectrum_figure") or {}
if C.check(figure.get("bars", 0) > figure.get("kept", 0) > 0,
           "report: spectrum figure of %s bars, %s kept" % (figure.get("bars"),
                                                            figure.get("kept"))):
    kept_bars, other_bars, bar_pixels = bar_counts(os.path.join(out, "spectrum.png"),
                                                   figure["kept_colour"],
                                                   figure["other_colour"])
    C.check(kept_bars == figure["kept"] and other_bars == figure["bars"] - figure["kept"]
            and bar_pixels > 5000,
            "spectrum.png: %d kept and %d other bars drawn (%d bar pixels)"
            % (kept_bars, other_bars, bar_pixels))


def panel_points(path, panels):
    """Pixels of widget-coloured points (saturated) and of grey points (190) in each of the
    `panels` equal parts of methods.png."""
    pixels = rgb_pixels(path).astype(int)
    spread = pixels.max(axis=2) - pixels.min(axis=2)
    coloured = spread > 100
    grey = (abs(pixels - 190).max(axis=2) <= 2)
    width = pixels.shape[1] // panels
    return [(int(coloured[:, i * width:(i + 1) * width].sum()),
             int(grey[:, i * width:(i + 1) * width].sum())) for i in range(panels)]


# methods.png: PCA, Isomap, LLE and UMAP side by side, each panel with points in widget colours.
methods = report.get("methods") or {}
names = ("PCA", "Isomap", "LLE", "UMAP")
C.check(all(name in methods and 0.5 < methods[name]["trustworthiness"] <= 1.0 for name in names),
        "report: trustworthiness of PCA, Isomap, LLE, UMAP on the same sample %s"
        % [round(methods.get(n, {}).get("trustworthiness", 0), 3) for n in names])
if os.path.exists(os.path.join(out, "methods.png")):
    counts = panel_points(os.path.join(out, "methods.png"), len(names))
    C.check(all(c > 200 and g > 1000 for c, g in counts),
            "methods.png: four panels with points, widget-coloured and grey (%s)" % counts)
    # Every shown widget's voxels in its colour in every panel, a faint widget's too (an
    # opacity threshold left the seeded "ch2 mid" widget, peak 0.09, without a point).
    shown_rgb = [[int(round(255 * v)) for v in w[4:7]] for w in report["widgets"] if w[7] > 0]
    pixels = rgb_pixels(os.path.join(out, "methods.png")).astype(int)
    width = pixels.shape[1] // len(names)
    per_panel = [[int((abs(pixels[:, i * width:(i + 1) * width] - rgb).max(axis=2) <= 12).sum())
                  for rgb in shown_rgb] for i in range(len(names))]
    C.check(len(shown_rgb) >= 2 and all(n >= 10 for row in per_panel for n in row),
            "methods.png: each shown widget's colour %s in every panel (pixels: %s)"
            % (shown_rgb, per_panel))


def hue(rgb):
    r, g, b = rgb
    mx, mn = max(rgb), min(rgb)
    if mx - mn < 1e-9:
        return None
    if mx == r:
        h = ((g - b) / (mx - mn)) % 6
    elif mx == g:
        h = (b - r) / (mx - mn) + 2
    else:
        h = (r - g) / (mx - mn) + 4
    return h / 6.0


image = mce._read_png(os.path.join(out, "best.png"))
pixels = image.GetPointData().GetScalars()
counts = [0] * len(report["widgets"])
for i in range(pixels.GetNumberOfTuples()):
    p = pixels.GetTuple(i)[:3]
    if max(p) - min(p) < 40:  # grey: background or faint
        continue
    h = hue([c / 255.0 for c in p])
    for w, widget in enumerate(report["widgets"]):
        wh = hue(widget[4:7])
        if wh is not None and min(abs(h - wh), 1 - abs(h - wh)) < 0.04:
            counts[w] += 1
C.check(sum(1 for c in counts if c > 50) >= 2,
        "best view shows the widgets' colours (pixels per widget hue: %s)" % counts)


def foreground_silhouette(camera):
    """Pixels (rows bottom-up, as vtkPNGReader's) whose ray meets the brain's foreground:
    the Foreground = 0.5 surface of the same channels, white on black, with best.png's
    camera; dilated by 4 pixels (the renderer fades the mask over up to a voxel)."""
    from paraview import simple
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    readers = [simple.OpenDataFile(T.data_file(n))
               for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
    features = simple.MultichannelFeatures(Input=simple.AppendAttributes(Input=readers),
                                           FeatureSet="6D")
    surface = simple.Contour(Input=features, ContourBy=["POINTS", "Foreground"],
                             Isosurfaces=[0.5])
    view = G.black_view(camera["size"])
    display = simple.Show(surface, view)
    simple.ColorBy(display, None)
    display.AmbientColor = display.DiffuseColor = [1, 1, 1]
    display.Ambient, display.Diffuse = 1.0, 0.0
    view.CameraPosition = camera["position"]
    view.CameraFocalPoint = camera["focal_point"]
    view.CameraViewUp = camera["view_up"]
    view.CameraViewAngle = camera["view_angle"]
    view.CameraParallelProjection = camera["parallel_projection"]
    view.CameraParallelScale = camera["parallel_scale"]
    path = os.path.join(out, "foreground_silhouette.png")
    simple.SaveScreenshot(path, view, ImageResolution=camera["size"])
    image = mce._read_png(path)
    w, h = image.GetDimensions()[:2]
    inside = vtk_to_numpy(image.GetPointData().GetScalars())[:, :3].max(axis=1).reshape(h, w) > 0
    grown = inside.copy()
    for dy in range(-4, 5):
        for dx in range(-4, 5):
            grown |= np.roll(np.roll(inside, dy, axis=0), dx, axis=1)
    return grown


# The model and the transfer function beside the pictures, listed in the report; they
# load: the widgets are the seeded ones, the model names the three channels and the method.
files = report.get("model_files") or {}
model_file, tf_file = os.path.join(out, "model.mcvmodel"), os.path.join(out, "transfer_function.mcvtf")
C.check(files.get("model") == model_file and files.get("transfer_function") == tf_file and
        os.path.exists(model_file) and os.path.exists(tf_file),
        "model.mcvmodel and transfer_function.mcvtf written beside the pictures and listed "
        "in report.json (%s)" % files)
try:
    tf = mce.read_transfer_function(tf_file)
    header = mce.read_model(model_file)
    read_error = None
except ValueError as e:
    tf, read_error = None, str(e)
C.check(tf is not None and tf.model == model_file and
        [tf.widgets[i:i + 8] for i in range(0, len(tf.widgets), 8)] == report["widgets"] and
        header["reduction"]["method"] == report["method"] and
        header["crc32"] == files.get("model_crc32") and
        sorted(header["features"]["channels"]) == sorted(tf.channels) and
        len(tf.channels) == 3,
        "the transfer function loads: its model found (checksum %s), the 3 seeded widgets "
        "exactly, the model's method %s and its 3 channels (%s)"
        % (files.get("model_crc32"), report["method"], read_error or tf.channels))
if tf is not None:
    # Loaded onto a display of the same channels: the model applies and every widget is back.
    from multichannel_explorer._common import _filter
    from paraview import simple

    volume = _filter("MergeChannels")(Input=[simple.OpenDataFile(T.data_file(n + ".nii.gz"))
                                             for n in T.BRAIN])
    reduction, shown = mce.apply_transfer_function(volume, tf_file,
                                                   simple.CreateView("RenderView"))
    reduction.UpdatePropertyInformation()
    outside = reduction.GetProperty("NumberOfOutOfModelVoxels").GetElement(0)
    C.check([float(v) for v in shown.GaussianWidgets] == tf.widgets and outside == 0,
            "apply_transfer_function on the job's own channels: the widgets set, no voxel "
            "out of the model (%d)" % outside)
    simple.Delete(reduction)

camera = report.get("best_camera")
if C.check(camera is not None, "report: best_camera recorded"):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    silhouette = foreground_silhouette(camera)
    w, h = image.GetDimensions()[:2]
    best_rgb = vtk_to_numpy(pixels)[:, :3].reshape(h, w, 3).astype(int)
    background = np.array([round(255 * c) for c in camera["background"]])
    outside = ~silhouette
    outside[: h // 4, : w // 4] = False  # the orientation axes (bottom left)
    outside[-(h // 4):, -(w // 2):] = False  # the widget legend (top right; rows bottom up)
    glow = outside & (np.abs(best_rgb - background).max(axis=2) > 2)
    print("silhouette covers %d of %d pixels; %d pixels outside it are not the background %s"
          % (silhouette.sum(), w * h, glow.sum(), background.tolist()))
    # the best view is fitted to what it shows (the brain fills ~3/4 of the picture), so the
    # pixels left outside the silhouette to look for a glow are fewer, still thousands
    C.check(silhouette.sum() > 0.05 * w * h and outside.sum() > 0.05 * w * h,
            "the brain's silhouette is neither empty nor everything (%.0f %% of the picture "
            "outside it, axes and legend corners left out)" % (100.0 * outside.sum() / (w * h)))
    C.check(glow.sum() <= 0.001 * outside.sum(),
            "no glow around the head: %d pixels outside the brain's silhouette differ from "
            "the background" % glow.sum())
C.finish()
