"""The "Gaussian TF Volume" representation on a synthetic volume with known coordinates,
with the classification given as the first argument ("Per sample", the default, or
"Per voxel"): every check holds for both.

A 32^3 image whose 3-component ReducedCoordinates is the voxel position / 31 (so [0,1]^3),
seen along -z with a parallel camera on a black background; pixel values are read at the
projections of the widget centres:
* two widgets, pure red at x=0.25 and pure green at x=0.75: red pixels where the red
  widget's voxels project, green at the other, dark in between and outside; composite and
  maximum intensity;
* colours are not stretched per channel: a single (0.4, 0.2, 0.1) widget renders as about
  (102, 51, 26), and a (0.5, 0, 0) widget beside a (0, 1, 0) one stays at half red;
* a widget edit recomputes the colours without delivering the volume again, a data change
  delivers and recomputes; 2-component (2D) and float64 coordinates work;
* bad inputs, each a clear error or warning, nothing drawn on an error, no crash: missing
  coordinate array, 1 component, a widget list whose length is not a multiple of 8,
  sigma <= 0, NaN, colours/opacity outside [0, 1] (clamped), no widgets (transparent).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402
import builtins as B  # noqa: E402  (a ProgrammableFilter script shadows max/min here)

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
CLASSIFICATION = sys.argv[1] if len(sys.argv) > 1 else "Per sample"
PER_SAMPLE = CLASSIFICATION == "Per sample"
C = T.Checker("test_gaussian_tf_representation (%s)" % CLASSIFICATION)

N = 32
RED = [0.25, 0.5, 0.5, 0.08, 1, 0, 0, 1]
GREEN = [0.75, 0.5, 0.5, 0.08, 0, 1, 0, 1]


def world(u):
    """World position of reduced coordinates u (voxel position / 31)."""
    return [c * (N - 1) for c in u]


wavelet = simple.Wavelet(WholeExtent=[0, N - 1, 0, N - 1, 0, N - 1])
calc = simple.Calculator(Input=wavelet, ResultArrayName="ReducedCoordinates",
                         ResultArrayType="Float", Function="coords/%d" % (N - 1))
calc.UpdatePipeline()

view = G.black_view()
display = simple.Show(calc, view)
C.check("Gaussian TF Volume" in display.GetProperty("Representation").Available,
        "'Gaussian TF Volume' is offered for image data")
display.SetRepresentationType("Gaussian TF Volume")
C.check(display.Representation == "Gaussian TF Volume", "SetRepresentationType works")
C.check(display.CoordinateArray == "ReducedCoordinates" and list(display.GaussianWidgets) == []
        and display.Device == "Auto" and display.GaussianBlendMode == "Composite",
        "defaults: CoordinateArray ReducedCoordinates, no widgets, Device Auto, Composite")
C.check(display.Classification == "Per sample" and display.Jittering == 1 and
        display.MaskArray == "Foreground",
        "defaults: Classification Per sample, Jittering on, MaskArray Foreground")
C.check(display.EmptySpaceSkipping == "Automatic", "default: EmptySpaceSkipping Automatic")
display.Classification = CLASSIFICATION
C.check(sorted(display.GetProperty("GaussianBlendMode").Available) ==
        ["Composite", "Maximum Intensity"], "blend modes: Composite, Maximum Intensity")

display.GaussianWidgets = RED + GREEN
G.look_down_z(view, [0, N - 1] * 3)
red_px = G.project(view, world(RED[:3]))
green_px = G.project(view, world(GREEN[:3]))
mid_px = G.project(view, world([0.5, 0.5, 0.5]))
corner_px = G.project(view, world([0.02, 0.05, 0.5]))
print("pixels: red %s green %s middle %s corner %s" % (red_px, green_px, mid_px, corner_px))
C.check(green_px[0] - red_px[0] > 100 and abs(green_px[1] - red_px[1]) <= 1,
        "the widget centres project to distinct pixels on one row")


def shot(name):
    return G.Shot(view, G.output_path(name))


def check_two_colours(label, s, red_channel=0, green_channel=1, min_value=100):
    red, green, mid, corner = (s.rgb(red_px), s.rgb(green_px), s.rgb(mid_px),
                               s.rgb(corner_px))
    print("%s: red %s green %s middle %s corner %s" % (label, red, green, mid, corner))
    C.check(G.is_colour(red, red_channel, min_value),
            "%s: the red widget's voxels are red %s" % (label, red))
    C.check(G.is_colour(green, green_channel, min_value),
            "%s: the green widget's voxels are green %s" % (label, green))
    C.check(B.max(mid) < 0.3 * B.max(B.max(red), B.max(green)),
            "%s: dark between the widgets %s" % (label, mid))
    C.check(B.max(corner) <= 10, "%s: background outside the widgets %s" % (label, corner))
    return red, green


def automatic_choice():
    """The information of a render with EmptySpaceSkipping Automatic; leaves it Off."""
    display.EmptySpaceSkipping = "Automatic"
    simple.Render(view)
    state = G.info(display)
    display.EmptySpaceSkipping = "Off"
    simple.Render(view)
    return state


# --- composite and maximum intensity --------------------------------------------
first = G.info(display)
print("info after the first render: %s" % first)
C.check(first["valid"] == 1 and first["computations"] >= 1 and first["data_updates"] >= 1,
        "rendered: colours computed and volume delivered %s" % first)
C.check(first["device"] == "OpenGL" if PER_SAMPLE else first["device"] in ("CPU", "GPU"),
        "DeviceUsed is OpenGL per sample, CPU or GPU per voxel (%s)" % first["device"])
check_two_colours("composite", shot("gaussian_tf_composite.png"))
if PER_SAMPLE:
    # Empty space skipping (bricks of 8^3 voxels: 4 x 4 x 4 here). Two widgets each reach
    # 0.42 = 5.3 sigma (where their opacity falls to 1e-6): no brick is empty, and a brick
    # that one of the two reaches evaluates both (a list pays below a third of them).
    state = G.skipping_unchanged(C, view, display, "composite", "gaussian_tf_composite")
    C.check(state["bricks"] == (64, 0, 2.0) and state["skipping_used"] == 1,
            "widget table: 64 bricks, none empty, both widgets everywhere (%s)"
            % (state["bricks"],))
    # Automatic leaves out a table that lists every widget everywhere: the loop over all.
    automatic = automatic_choice()
    C.check(automatic["skipping_used"] == 0 and automatic["bricks"] == (64, 0, 2.0),
            "Automatic: no bricks where both widgets reach every brick (%s)" % (automatic,))
    # 16 narrow widgets on a 4 x 4 grid in the plane z = 0.5 (sigma 0.02, reach 0.105):
    # each reaches the two middle z-bricks of its own x, y column (and at most a
    # neighbour's), so 32 bricks are empty and the other 32 list one or two widgets each.
    grid = []
    for a in range(4):
        for b in range(4):
            grid += [0.125 + 0.25 * a, 0.125 + 0.25 * b, 0.5, 0.02,
                     (a + 1) / 4.0, (b + 1) / 4.0, 1 - (a + b) / 6.0, 1]
    display.GaussianWidgets = grid
    state = G.skipping_unchanged(C, view, display, "16 widgets", "gaussian_tf_grid16")
    C.check(state["bricks"][:2] == (64, 32) and 1.0 <= state["bricks"][2] <= 2.0,
            "16 widgets: 32 empty bricks, 1 to 2 listed widgets per other brick (%s)"
            % (state["bricks"],))
    # Automatic takes these bricks (at most 2 of 16 widgets per sample), and draws what
    # the un-culled loop draws.
    automatic = automatic_choice()
    C.check(automatic["skipping_used"] == 1,
            "Automatic: the bricks with 16 narrow widgets (%s)" % (automatic,))
    off_shot = G.Shot(view, G.output_path("gaussian_tf_grid16_no_skipping.png"))
    display.EmptySpaceSkipping = "Automatic"
    simple.Render(view)
    auto_shot = G.Shot(view, G.output_path("gaussian_tf_grid16_automatic.png"))
    largest, share = G.difference(auto_shot, off_shot)
    C.check(auto_shot.max_channel() > 30 and largest <= 8 and share <= 0.001,
            "Automatic vs Off, 16 widgets: largest difference %d/255, %.4f %% of pixels "
            "> 2/255" % (largest, 100 * share))
    display.EmptySpaceSkipping = "Off"
    display.GaussianWidgets = RED + GREEN
    simple.Render(view)

before = G.info(display)
display.GaussianBlendMode = "Maximum Intensity"
simple.Render(view)
red, green = check_two_colours("maximum intensity", shot("gaussian_tf_mip.png"),
                               min_value=180)
after = G.info(display)
C.check(after["computations"] == before["computations"] and
        after["data_updates"] == before["data_updates"],
        "a blend-mode change neither recomputes nor re-delivers %s -> %s" % (before, after))

# --- no per-channel stretching (MIP shows the colour of the most opaque sample) -------
display.GaussianWidgets = [0.5, 0.5, 0.5, 0.1, 0.4, 0.2, 0.1, 1]
simple.Render(view)
s = shot("gaussian_tf_mip_unstretched.png")
centre = s.rgb(mid_px)
print("(0.4, 0.2, 0.1) widget, MIP centre pixel %s (expected about 255*alpha*(0.4, 0.2, 0.1)"
      ", alpha ~0.95: (97, 48, 24))" % centre)
C.check(85 <= centre[0] <= 110 and abs(centre[1] - centre[0] / 2.0) <= 6 and
        abs(centre[2] - centre[0] / 4.0) <= 6,
        "colour (0.4, 0.2, 0.1) rendered unstretched %s" % centre)

display.GaussianWidgets = [0.25, 0.5, 0.5, 0.08, 0.5, 0, 0, 1] + GREEN
simple.Render(view)
s = shot("gaussian_tf_mip_half_red.png")
half_red, full_green = s.rgb(red_px), s.rgb(green_px)
print("(0.5, 0, 0) and (0, 1, 0) widgets, MIP: %s %s" % (half_red, full_green))
C.check(G.is_colour(half_red, 0, 90) and half_red[0] <= 135 and
        G.is_colour(full_green, 1, 180) and full_green[1] > 1.6 * half_red[0],
        "half red stays half as bright as full green %s %s" % (half_red, full_green))

# --- widget edits recompute without re-delivery; data changes re-deliver ---------------
display.GaussianBlendMode = "Composite"
display.GaussianWidgets = RED + GREEN
simple.Render(view)
before = G.info(display)
display.GaussianWidgets = [0.25, 0.5, 0.5, 0.08, 0, 1, 0, 1, 0.75, 0.5, 0.5, 0.08, 1, 0, 0, 1]
simple.Render(view)
after = G.info(display)
check_two_colours("swapped colours", shot("gaussian_tf_swapped.png"), 1, 0)
C.check(after["computations"] == before["computations"] + 1,
        "a widget edit recomputes once %s -> %s" % (before, after))
C.check(after["data_updates"] == before["data_updates"],
        "a widget edit does not deliver the volume again %s -> %s" % (before, after))
C.check(after["texture_builds"] == before["texture_builds"],
        "a widget edit builds no texture %s -> %s" % (before, after))
simple.Render(view)
C.check(G.info(display)["computations"] == after["computations"],
        "a plain re-render computes nothing")

display.GaussianWidgets = RED + GREEN
calc.Function = "(1-coordsX/%d)*iHat+coordsY/%d*jHat+coordsZ/%d*kHat" % ((N - 1,) * 3)
simple.Render(view)
mirrored = G.info(display)
check_two_colours("mirrored coordinates", shot("gaussian_tf_mirrored.png"), 1, 0)
C.check(mirrored["data_updates"] > after["data_updates"] and
        mirrored["computations"] > after["computations"],
        "a data change re-delivers and recomputes %s -> %s" % (after, mirrored))
C.check(mirrored["texture_builds"] == after["texture_builds"] + (1 if PER_SAMPLE else 0),
        "a data change builds the texture once per sample, never per voxel %s -> %s"
        % (after, mirrored))
calc.Function = "coords/%d" % (N - 1)

# float64 coordinates are converted
calc.ResultArrayType = "Double"
simple.Render(view)
check_two_colours("float64 coordinates", shot("gaussian_tf_double.png"))
calc.ResultArrayType = "Float"

# 2D coordinates (x, y): the widgets' third centre coordinate is ignored
two_d = G.coords_2d(calc, N)
simple.Hide(calc, view)
display2 = mce.show_gaussian_tf(
    two_d, view, widgets=[[0.25, 0.5, 99.0, 0.08, 1, 0, 0, 1], [0.75, 0.5, -7.0, 0.08, 0, 1, 0, 1]],
    coordinates="Coords2D")
simple.Render(view)
C.check(display2.Representation == "Gaussian TF Volume" and
        display2.CoordinateArray == "Coords2D" and len(display2.GaussianWidgets) == 16,
        "show_gaussian_tf sets the representation, array and widgets")
C.check(G.info(display2)["valid"] == 1, "2D coordinates are accepted")
check_two_colours("2D coordinates", shot("gaussian_tf_2d.png"))
simple.Hide(two_d, view)
display = simple.Show(calc, view)
simple.Render(view)

# --- bad inputs ----------------------------------------------------------------------
msgs = G.messages(display)


def bad(label, error_words=None, warning_words=None, drawn=False, **props):
    msgs.clear()
    for name, value in props.items():
        setattr(display, name, value)
    simple.Render(view)
    s = shot("gaussian_tf_bad_%s.png" % label)
    state = G.info(display)
    print("%s: errors %s warnings %s info %s max pixel %d"
          % (label, msgs.errors, msgs.warnings, state, s.max_channel()))
    if error_words:
        C.check(msgs.any_error(*error_words), "%s: error mentioning %s" % (label, error_words))
        C.check(state["valid"] == 0, "%s: marked invalid" % label)
    else:
        C.check(not msgs.errors, "%s: no error" % label)
    if warning_words:
        C.check(msgs.any_warning(*warning_words),
                "%s: warning mentioning %s" % (label, warning_words))
    if not drawn:
        C.check(s.max_channel() <= 10, "%s: nothing drawn (max pixel %d)"
                % (label, s.max_channel()))
    return s


bad("missing_array", ["NoSuchArray", "not", "point array"], CoordinateArray="NoSuchArray")
bad("one_component", ["RTData", "1 component", "2 or 3"], CoordinateArray="RTData")
display.CoordinateArray = "ReducedCoordinates"
bad("length_7", ["7 values", "multiple of 8"], GaussianWidgets=RED[:7])
bad("length_9", ["9 values", "multiple of 8"], GaussianWidgets=RED + [0.5])
bad("sigma_zero", ["sigma", "must be > 0"], GaussianWidgets=[0.25, 0.5, 0.5, 0, 1, 0, 0, 1])
bad("sigma_negative", ["sigma", "must be > 0"],
    GaussianWidgets=RED + [0.75, 0.5, 0.5, -0.1, 0, 1, 0, 1])
bad("nan", ["not finite"], GaussianWidgets=[0.25, 0.5, float("nan"), 0.08, 1, 0, 0, 1])
s = bad("clamped", None, ["outside [0, 1]", "clamped"], drawn=True,
        GaussianWidgets=[0.25, 0.5, 0.5, 0.08, 2.0, -1.0, 0.0, 1.5] + GREEN)
C.check(G.is_colour(s.rgb(red_px), 0, 100) and G.is_colour(s.rgb(green_px), 1, 100),
        "clamped colours render as red and green %s %s" % (s.rgb(red_px), s.rgb(green_px)))
C.check(G.info(display)["valid"] == 1, "clamped: still valid")
bad("no_widgets", None, ["no gaussian widgets", "transparent"], GaussianWidgets=[])
C.check(G.info(display)["valid"] == 1, "no widgets: valid (a transparent volume)")

# 64 widgets are the shader's limit: 65 is an error per sample, fine per voxel
far = [5.0, 5.0, 5.0, 0.1, 1, 1, 1, 1]
if PER_SAMPLE:
    bad("65_widgets", ["65 visible Gaussian widgets", "at most 64", "Per voxel"],
        GaussianWidgets=RED + GREEN + far * 63)
    bad("64_widgets", None, drawn=True, GaussianWidgets=RED + GREEN + far * 62)
    C.check(G.info(display)["valid"] == 1, "64 widgets: valid per sample")
else:
    bad("65_widgets", None, drawn=True, GaussianWidgets=RED + GREEN + far * 63)
    C.check(G.info(display)["valid"] == 1, "65 widgets: valid per voxel")

# GPU requested: runs there, or falls back to the CPU with a warning (per voxel; per
# sample classifies in OpenGL whatever Device says)
msgs.clear()
display.Device = "GPU"
display.GaussianWidgets = RED + GREEN
simple.Render(view)
used = G.info(display)["device"]
print("Device GPU -> ran on %s; warnings %s" % (used, msgs.warnings))
C.check(used == "OpenGL" if PER_SAMPLE else (used == "GPU" or msgs.any_warning("GPU", "CPU")),
        "Device GPU: OpenGL per sample; per voxel on the GPU or a warning about the CPU "
        "fallback (%s)" % used)
check_two_colours("after bad inputs (recovered)", shot("gaussian_tf_recovered.png"))

C.finish()
