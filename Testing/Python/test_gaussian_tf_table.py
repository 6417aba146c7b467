"""The "Gaussian TF Volume" per sample through the baked table (PerSampleEvaluation "Baked
table") against the exact evaluation of every widget ("Exact", the default), on a
synthetic volume with known coordinates.

A 48^3 image whose 3-component ReducedCoordinates is the voxel position / 47 (so [0,1]^3),
seen obliquely with a perspective camera on a black background. Checks:
* the table's size follows its rule (mcvGaussianTFTable.h: 3 intervals per sigma of the
  narrowest widget on each axis, plus one): sigma 0.08 on extent 1 -> 39 nodes per axis;
  a widget edit bakes it again (sigma 0.1 -> 31); 2D coordinates -> one node in z;
* a widget too narrow for the largest table (sigma 0.005 -> 601 nodes on an axis, more
  than 512; sigma 0.012 -> 251^3 nodes in all, more than 2^23) falls back to the exact
  evaluation and says why;
* the pictures through the table and exact agree within the tolerance for 2, 8 and 64
  widgets, composite and maximum intensity, with and without empty space skipping
  (TOLERANCE: composite: no channel more than 6/255 apart, at most 0.5 % of the pixels
  more than 2/255; maximum intensity: 99.9 % of the pixels' brightness within 6/255, as a
  ray whose two most opaque samples, of two widgets, nearly tie may show either one's
  colour, and at most 3 % more than 2/255: a ray shows its one most opaque sample, so the
  table's error at a widget's peak is not averaged along the ray);
* the tolerance can fail: the exact picture against the table's picture of the same
  widgets with one centre moved by a third of its sigma is outside it (composite and
  maximum intensity);
* "Exact" says so, and a widget edit neither re-delivers the volume nor rebuilds the
  coordinate texture.
Screenshots go to the test output folder.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402
import builtins as B  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_gaussian_tf_table")

N = 48
LARGEST, SHARE = 6, 0.005  # TOLERANCE: largest channel difference /255, share > 2/255
MIP_SHARE = 0.03  # maximum intensity: share of pixels whose brightness is > 2/255 apart


def difference(a, b, maximum_intensity=False):
    """(largest difference, share of pixels more than 2/255 apart) of two Shots: of the
    channels, or with `maximum_intensity` of the brightness (largest channel) and its
    99.9th percentile in place of the largest."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    x = vtk_to_numpy(a.scalars)[:, :3].astype(np.int32)
    y = vtk_to_numpy(b.scalars)[:, :3].astype(np.int32)
    if maximum_intensity:
        d = np.abs(x.max(axis=1) - y.max(axis=1))
        return int(np.percentile(d, 99.9)), float((d > 2).mean())
    d = np.abs(x - y).max(axis=1)
    return int(d.max()), float((d > 2).mean())

wavelet = simple.Wavelet(WholeExtent=[0, N - 1, 0, N - 1, 0, N - 1])
calc = simple.Calculator(Input=wavelet, ResultArrayName="ReducedCoordinates",
                         ResultArrayType="Float", Function="coords/%d" % (N - 1))
calc.UpdatePipeline()

view = G.black_view((400, 400))
display = mce.show_gaussian_tf(calc, view)
display.ShowWidgetLegend = 0
C.check(display.PerSampleEvaluation == "Exact", "default: PerSampleEvaluation Exact")
C.check(sorted(display.GetProperty("PerSampleEvaluation").Available) == ["Baked table", "Exact"],
        "PerSampleEvaluation offers Baked table and Exact")

PALETTE = [(0.89, 0.10, 0.11), (0.22, 0.49, 0.72), (0.30, 0.69, 0.29), (0.60, 0.31, 0.64),
           (1.00, 0.50, 0.00), (1.00, 1.00, 0.20), (0.65, 0.34, 0.16), (0.97, 0.51, 0.75)]


def widget(centre, sigma, colour, opacity):
    return list(centre) + [sigma] + list(colour) + [opacity]


TWO = widget((0.3, 0.5, 0.5), 0.08, (1, 0, 0), 0.6) + widget((0.7, 0.5, 0.5), 0.08, (0, 1, 0), 0.6)
EIGHT = []
for i in range(8):
    a = i / 8.0
    EIGHT += widget((0.5 + 0.3 * (a - 0.5), 0.2 + 0.6 * ((3 * i) % 8) / 7.0, 0.3 + 0.4 * (i % 3) / 2.0),
                    0.05 + 0.01 * (i % 4), PALETTE[i], 0.3 + 0.05 * i)
SIXTY_FOUR = []
for i in range(4):
    for j in range(4):
        for k in range(4):
            SIXTY_FOUR += widget((0.125 + 0.25 * i, 0.125 + 0.25 * j, 0.125 + 0.25 * k), 0.06,
                                 PALETTE[(i + 2 * j + 3 * k) % 8], 0.4)

simple.Render(view)
camera = view.GetActiveCamera()
view.CameraPosition = [-0.9 * N, -1.4 * N, 1.9 * N]
view.CameraFocalPoint = [N / 2.0, N / 2.0, N / 2.0]
view.CameraViewUp = [0, 0, 1]
view.CameraParallelProjection = 0
simple.Render(view)


def render(name, evaluation, widgets, blend="Composite", skipping=0):
    display.PerSampleEvaluation = evaluation
    display.GaussianWidgets = widgets
    display.GaussianBlendMode = blend
    display.EmptySpaceSkipping = skipping
    simple.Render(view)
    return G.Shot(view, G.output_path(name + ".png")), G.info(display)


def used():
    display.UpdatePropertyInformation()
    return str(display.GetPropertyValue("GaussianTFEvaluationUsed"))


def compare(label, stem, widgets, blend="Composite", skipping=0, expect_used=None):
    table, state = render(stem + "_table", "Baked table", widgets, blend, skipping)
    how = used()
    exact, _ = render(stem + "_exact", "Exact", widgets, blend, skipping)
    largest, share = difference(table, exact, blend == "Maximum Intensity")
    print("%s: %s; table vs exact: largest %d/255, %.3f %% of pixels > 2/255; max %d"
          % (label, how, largest, 100 * share, exact.max_channel()))
    C.check(state["valid"] == 1 and exact.max_channel() > 60,
            "%s: drawn (brightest channel %d)" % (label, exact.max_channel()))
    if expect_used is not None:
        C.check(how == expect_used, "%s: evaluation '%s' (expected '%s')" % (label, how, expect_used))
    limit = MIP_SHARE if blend == "Maximum Intensity" else SHARE
    C.check(largest <= LARGEST and share <= limit,
            "%s: the table's picture is the exact one within %d/255 (largest %d/255, %.3f %% "
            "of pixels > 2/255, at most %.1f %%)" % (label, LARGEST, largest, 100 * share, 100 * limit))
    return table, exact


# --- the table's size and the pictures ----------------------------------------------------
table2, exact2 = compare("2 widgets, composite", "table_two", TWO, expect_used="table 39x39x39")
mip_table2, mip_exact2 = compare("2 widgets, maximum intensity", "table_two_mip", TWO,
                                 "Maximum Intensity", expect_used="table 39x39x39")
compare("8 widgets, composite", "table_eight", EIGHT, expect_used="table 61x61x61")
compare("8 widgets, maximum intensity", "table_eight_mip", EIGHT, "Maximum Intensity")
compare("64 widgets, composite", "table_sixty_four", SIXTY_FOUR, expect_used="table 51x51x51")
compare("64 widgets, composite, empty space skipping", "table_sixty_four_skipping", SIXTY_FOUR,
        skipping=1, expect_used="table 51x51x51")
compare("64 widgets, maximum intensity", "table_sixty_four_mip", SIXTY_FOUR, "Maximum Intensity")

# --- the tolerance can fail: one centre moved by a third of its sigma ----------------------
moved = list(TWO)
moved[0] += 0.08 / 3.0
shifted, _ = render("table_two_moved", "Baked table", moved)
largest, share = difference(shifted, exact2)
print("a centre moved by sigma/3, table vs exact of the unmoved: largest %d/255, %.3f %%"
      % (largest, 100 * share))
C.check(largest > LARGEST or share > SHARE,
        "the comparison sees a centre moved by sigma/3 (largest %d/255, %.3f %% of pixels > 2/255)"
        % (largest, 100 * share))
shifted, _ = render("table_two_mip_moved", "Baked table", moved, "Maximum Intensity")
largest, share = difference(shifted, mip_exact2, True)
print("maximum intensity, a centre moved by sigma/3: 99.9th percentile %d/255, %.3f %%"
      % (largest, 100 * share))
C.check(largest > LARGEST or share > MIP_SHARE,
        "maximum intensity: the comparison sees a centre moved by sigma/3 (99.9th percentile "
        "%d/255, %.3f %% of pixels > 2/255)" % (largest, 100 * share))

# --- a widget edit bakes again; no re-delivery, no new coordinate texture ----------------
render("table_two", "Baked table", TWO)
before = G.info(display)
wider = list(TWO)
wider[3] = wider[11] = 0.1
render("table_two_wider", "Baked table", wider)
after = G.info(display)
C.check(used() == "table 31x31x31", "sigma 0.1: a 31^3 table (%s)" % used())
C.check(after["computations"] == before["computations"] + 1 and
        after["data_updates"] == before["data_updates"] and
        after["texture_builds"] == before["texture_builds"],
        "a widget edit bakes again without re-delivery or a new coordinate texture %s -> %s"
        % (before, after))

# --- too narrow for the table: every widget, and why ----------------------------------------
narrow = TWO[:3] + [0.005] + TWO[4:]
s, state = render("table_narrow", "Baked table", narrow)
how = used()
print("sigma 0.005: %s" % how)
C.check(how.startswith("exact: ") and "601" in how and "512" in how,
        "sigma 0.005 needs 601 nodes on an axis: exact, and why (%s)" % how)
C.check(state["valid"] == 1 and s.max_channel() > 60, "sigma 0.005: drawn")
total = TWO[:3] + [0.012] + TWO[4:]
render("table_total", "Baked table", total)
how = used()
C.check(how.startswith("exact: ") and "251 x 251 x 251" in how,
        "sigma 0.012 needs 251^3 nodes, more than the table holds: exact, and why (%s)" % how)
render("table_exact", "Exact", TWO)
C.check(used() == "exact", "PerSampleEvaluation Exact: '%s'" % used())

# --- 2D coordinates: one node in z; a constant component: one node ------------------------
flat = simple.Calculator(Input=wavelet, ResultArrayName="Flat", ResultArrayType="Float",
                         Function="coordsX/%d*iHat+coordsY/%d*jHat+0.5*kHat" % (N - 1, N - 1))
two_d = G.coords_2d(calc, N)
for coordinate_source, array, label, expected in ((flat, "Flat", "constant z", "table 39x39x1"),
                                       (two_d, "Coords2D", "2D coordinates", "table 39x39x1")):
    simple.Hide(calc, view)
    d = mce.show_gaussian_tf(coordinate_source, view, widgets=TWO, coordinates=array)
    d.ShowWidgetLegend = 0
    d.PerSampleEvaluation = "Baked table"
    simple.Render(view)
    d.UpdatePropertyInformation()
    how = str(d.GetPropertyValue("GaussianTFEvaluationUsed"))
    a = G.Shot(view, G.output_path("table_%s.png" % label.replace(" ", "_")))
    d.PerSampleEvaluation = "Exact"
    simple.Render(view)
    b = G.Shot(view, G.output_path("table_%s_exact.png" % label.replace(" ", "_")))
    largest, share = difference(a, b)
    print("%s: %s; table vs exact largest %d/255, %.3f %%" % (label, how, largest, 100 * share))
    C.check(how == expected, "%s: '%s' (expected '%s')" % (label, how, expected))
    C.check(b.max_channel() > 60 and largest <= LARGEST and share <= SHARE,
            "%s: the table's picture is the exact one within %d/255 (largest %d/255)"
            % (label, LARGEST, largest))
    simple.Hide(coordinate_source, view)

C.finish()
