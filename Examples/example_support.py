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
            # A default worth showing: not None, False (a flag) or a required option's.
            default = action.default
            if action.help and "%(default)" not in action.help and not action.required and \
                    not any(default is v for v in (None, False, argparse.SUPPRESS)):
                shown = " ".join(map(str, default)) if isinstance(default, (list, tuple)) \
                    else "%(default)s"
                return "%s (default: %s)" % (action.help, shown)
            return action.help

    return argparse.ArgumentParser(description=doc, formatter_class=Formatter)


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
