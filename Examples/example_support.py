"""What every example script needs: finding and loading the MultichannelExplorer plugin,
and a render view with the examples' look. Import it from an example with
``sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))``."""
import glob
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
DATA = os.environ.get("MCV_DATA_DIR") or os.path.join(REPO, ".cache", "volumes")


def argument_parser(doc):
    """An argparse parser whose --help shows the script's whole docstring `doc` as written
    and each option's default (where it has one)."""
    import argparse

    class Formatter(argparse.RawDescriptionHelpFormatter):
        def _get_help_string(self, action):
            # A default worth showing: not a flag's, None, a required option's or
            # one the help names already.
            default = action.default
            if action.help and "default" not in action.help and not action.required and \
                    action.nargs != 0 and \
                    not any(default is v for v in (None, False, argparse.SUPPRESS)):
                shown = " ".join(map(str, default)) if isinstance(default, (list, tuple)) \
                    else "%(default)s"
                return "%s (default: %s)" % (action.help, shown)
            return action.help

    return argparse.ArgumentParser(description=doc, formatter_class=Formatter)


def add_output_options(parser, output, size, what="the pictures"):
    """--output (default `output`, none: required), --size W H (default `size`) and
    --plugin, as every example takes them."""
    parser.add_argument("--output", default=output, required=output is None, metavar="DIR",
                        help="the folder of %s" % what)
    parser.add_argument("--size", type=int, nargs=2, default=list(size), metavar=("W", "H"),
                        help="the pictures' size in pixels")
    parser.add_argument("--plugin", default=None,
                        help="the MultichannelExplorer plugin library (none: $MCV_PLUGIN, "
                             "then PV_PLUGIN_PATH, then build*/ of this repository)")


def add_reduction_options(parser, method, features):
    """The reduction and the seeded widgets, as the main job and the time-series example
    take them: --method, --features, --reference-size, --widgets, --widget-opacity."""
    parser.add_argument("--method", default=method, choices=["PCA", "Isomap", "LLE", "UMAP"],
                        help="the dimension reduction (Isomap: landmark Isomap)")
    parser.add_argument("--features", default=features, choices=["6D", "24D"],
                        help="features per channel: 6D intensity and gradient magnitude (2 "
                             "per channel), 24D all 8 (intensity, gradient x y z and "
                             "magnitude, Laplacian, 3x3x3 mean and variance)")
    parser.add_argument("--reference-size", type=int, default=10000,
                        help="voxels the embedding is fitted on")
    parser.add_argument("--widgets", type=int, default=4,
                        help="number of widgets seeded at k-means clusters")
    parser.add_argument("--widget-opacity", type=float, default=0.5,
                        help="the seeded widgets' peak opacity (the cluster of most voxels "
                             "gets 0.05 of it or starts hidden: auto_widgets)")


def find_plugin(explicit=None):
    """The plugin library: `explicit`, $MCV_PLUGIN, PV_PLUGIN_PATH, <repo>/build*/..."""
    candidates = [explicit, os.environ.get("MCV_PLUGIN")]
    for d in os.environ.get("PV_PLUGIN_PATH", "").split(os.pathsep):
        if d:
            candidates.append(os.path.join(d, "MultichannelExplorer.so"))
    candidates += sorted(glob.glob(os.path.join(
        REPO, "build*", "lib", "paraview-*", "plugins", "MultichannelExplorer",
        "MultichannelExplorer.so")))
    for c in candidates:
        if c and os.path.exists(c):
            return c
    sys.exit("MultichannelExplorer plugin not found: build the project (see README) or "
             "pass --plugin PATH")


def load_plugin(explicit=None):
    """Loads the plugin unless PV_PLUGIN_PATH already did; returns multichannel_explorer.
    The plugin's filters are then in paraview.simple (simple.BestViewpoint, ...)."""
    from paraview import simple

    if not hasattr(simple, "BestViewpoint"):
        simple.LoadPlugin(find_plugin(explicit), remote=False)
    import multichannel_explorer

    return multichannel_explorer


def render_view(size, background=(0.1, 0.1, 0.12)):
    """A render view of `size` pixels with a dark background and the orientation axes."""
    from paraview import simple

    view = simple.CreateView("RenderView")
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 1
    view.Background = list(background)
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    return view


def require(path):
    """Exits with 125 (CTest: skipped) when an input volume is missing."""
    if not os.path.exists(path):
        print("volume not found: %s (run scripts/fetch-data.sh first)" % path)
        sys.exit(125)
    return path
