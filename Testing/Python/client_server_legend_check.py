"""The Gaussian widget legend is in the picture in a built-in session AND in a client
connected to a (MPI) pvserver, where the volume stays on the server and only the client
draws the view's annotations.

Run as
  pvpython client_server_legend_check.py --out DIR
      a built-in session;
  pvpython client_server_legend_check.py --out DIR --connect PORT
      connected to a pvserver on localhost:PORT (the plugin loaded on both sides).
Both: the real brain (ch2 + AAL + Brodmann, every 3rd voxel), PCA 6D -> 3D, shown as a
"Gaussian TF Volume" with three widgets of known colours and names, rendered on the server
when there is one (RemoteRenderThreshold 0). Known answers:
- the legend's top-right area of the screenshot holds pixels of each widget's colour (its
  swatch: the exact bytes, a 2D polygon drawn without lighting), at least MIN_SWATCH of
  each, all of them inside the legend's box (x > half the view, y < 100 pixels);
- with ShowWidgetLegend 0 the same area holds none of them (the pixels are the legend's,
  not the volume's), and the volume itself is drawn (not the background only);
- a hidden widget (opacity 0) has no swatch.
Screenshots go to DIR (legend_<mode>.png, no_legend_<mode>.png).
Driver: test_client_server_legend.sh.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

VIEW_SIZE = [500, 400]
# Widget colours whose bytes the volume's blended colours are very unlikely to hit
# exactly: each swatch is matched within COLOUR_TOLERANCE per channel.
COLOURS = [(230, 25, 25), (25, 205, 50), (50, 75, 240), (240, 200, 20)]
NAMES = ["Alpha", "Beta", "Gamma", "Hidden"]
COLOUR_TOLERANCE = 6
MIN_SWATCH = 20  # pixels; a swatch of about 10 x 10 pixels at 20 pixels a row


def parse():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument("--connect", type=int, metavar="PORT")
    return parser.parse_args()


def load(port):
    if port is None:
        return T.load_plugin(globals())
    if simple.Connect("localhost", port) is None:
        print("FAIL: could not connect to a pvserver on localhost:%d" % port)
        sys.stdout.flush()
        os._exit(1)
    plugin = os.environ["MCV_PLUGIN"]
    simple.LoadPlugin(plugin, remote=True)
    simple.LoadPlugin(plugin, remote=False)
    import multichannel_explorer

    return multichannel_explorer


def pixels(path):
    """(height, width, 3) numpy array of a PNG, row 0 at the TOP of the picture."""
    import numpy as np

    (w, h, _), n, data = T._png_pixels(path)
    return np.frombuffer(data, dtype=np.uint8).reshape(h, w, n)[::-1, :, :3].astype(int)


def swatch_pixels(picture, colour):
    """(count in the legend's area, count elsewhere) of the pixels of `colour`."""
    import numpy as np

    near = (np.abs(picture - np.array(colour)) <= COLOUR_TOLERANCE).all(axis=2)
    h, w = near.shape
    area = np.zeros_like(near)
    area[:100, w // 2:] = True
    return int((near & area).sum()), int((near & ~area).sum())


def main():
    args = parse()
    mode = "client_server" if args.connect is not None else "builtin"
    C = T.Checker("client_server_legend_check (%s)" % mode)
    mce = load(args.connect)
    os.makedirs(args.out, exist_ok=True)

    volume = T.brain_subset(3)
    _, reduction = mce.reduce_multichannel(volume, "PCA", "6D", output_dimension=3,
                                           ReferenceSampleSize=3000, RandomSeed=7)
    reduction.UpdatePipeline()
    ranges = [reduction.PointData["ReducedCoordinates"].GetRange(c) for c in range(3)]
    span = max(hi - lo for lo, hi in ranges)
    centre = [(lo + hi) / 2.0 for lo, hi in ranges]
    widgets = []
    for w, colour in enumerate(COLOURS):
        x = centre[0] + (w - 1) * 0.15 * span
        opacity = 0.0 if NAMES[w] == "Hidden" else 0.6
        widgets += [x, centre[1], centre[2], 0.12 * span] + [c / 255.0 for c in colour] + [opacity]

    view = T.render_view(VIEW_SIZE, background=(0.0, 0.0, 0.0))
    view.RemoteRenderThreshold = 0  # render on the server when there is one
    display = mce.show_gaussian_tf(reduction, view, widgets=widgets)
    display.GaussianWidgetNames = NAMES
    simple.ResetCamera(view)

    shots = {}
    for shown in (1, 0):
        display.ShowWidgetLegend = shown
        simple.Render(view)
        path = os.path.join(args.out, "%s_%s.png" % ("legend" if shown else "no_legend", mode))
        simple.SaveScreenshot(path, view, ImageResolution=VIEW_SIZE)
        shots[shown] = pixels(path)

    for w, colour in enumerate(COLOURS):
        inside, outside = swatch_pixels(shots[1], colour)
        gone, _ = swatch_pixels(shots[0], colour)
        if NAMES[w] == "Hidden":
            C.check(inside == 0, "%s: the hidden widget's colour %s is not in the legend "
                    "(%d pixels)" % (mode, colour, inside))
            continue
        C.check(inside >= MIN_SWATCH and gone == 0,
                "%s: the legend shows %s's swatch %s (%d pixels in the top-right area with "
                "the legend, %d without it; %d elsewhere)" % (mode, NAMES[w], colour, inside,
                                                             gone, outside))
    lit = (abs(shots[0] - shots[0][0, 0]).max(axis=2) > 20).mean()
    C.check(lit > 0.05, "%s: the volume is drawn (%.1f%% of the pixels are not the "
            "background)" % (mode, 100.0 * lit))
    C.finish()


main()
