"""What the gui_NAME_setup.py scripts share. They run in the GUI's own Python
(`paraview --script=`, before ParaView plays gui_NAME_click.xml) and find this module
through PYTHONPATH, which their drivers set (test_gui.sh, test_gui_server.sh,
scripts/screenshot-gui-test.sh): a --script has no __file__ to find it by.

  output_dir()          $MCV_OUTPUT_DIR (default: the working folder), created
  data_path(name)       a file of $MCV_DATA_DIR
  removed(path)         `path`, an earlier run's file there removed
  open_active(name, state)
                        a data file opened, shown and made the active source
  State(name, ...)      what the test records for gui_NAME_check.py, saved as JSON
  screenshot(path, ...) a screenshot of the whole screen, taken in the background
"""
import json
import os
import subprocess


def output_dir():
    out = os.environ.get("MCV_OUTPUT_DIR", ".")
    os.makedirs(out, exist_ok=True)
    return out


def data_path(name):
    return os.path.join(os.environ.get("MCV_DATA_DIR", "."), name)


def removed(path):
    """`path` with no file there (a screenshot or a saved file of an earlier run would
    pass for this run's)."""
    if os.path.lexists(path):
        os.remove(path)
    return path


def open_active(name, state):
    """The data file `name` opened, shown in the active render view and made the active
    source; None when it is missing. state["data"] says whether it was there (the check
    script skips the test without it)."""
    from paraview import simple

    path = data_path(name)
    state["data"] = os.path.exists(path)
    if not state["data"]:
        return None
    reader = simple.OpenDataFile(path)
    view = simple.GetActiveViewOrCreate("RenderView")
    simple.Show(reader, view)
    simple.Render(view)
    simple.SetActiveSource(reader)
    return reader


class State(dict):
    """What the test records: a dict (its first items `initial`) that save() writes as JSON
    to $MCV_GUI_STATE (default `in_folder`/gui_NAME_state.json, `in_folder` the output
    folder by default). The setup scripts save after every change, so that a GUI that
    hangs or crashes still leaves what it did."""

    def __init__(self, name, in_folder=None, **initial):
        dict.__init__(self, initial)
        self.path = os.environ.get("MCV_GUI_STATE") or os.path.join(
            in_folder or output_dir(), "gui_%s_state.json" % name)

    def save(self):
        with open(self.path, "w") as f:
            json.dump(self, f, indent=1)


# Without a window manager, -geometry is not always honoured: the window is placed and
# sized here (1600x1000 at the origin), then the left docks are widened by dragging their
# edge (x = 294 in that layout) so that the Properties panel shows the editor unclipped.
_PLACE_WINDOW = """
window=$(xdotool search --onlyvisible --name ParaView 2>/dev/null | head -n 1)
if [ -n "$window" ]; then
  xdotool windowmove "$window" 0 0 windowsize "$window" 1600 1000
  sleep 1
  xdotool mousemove 294 300 sleep 0.3 mousedown 1 sleep 0.3 mousemove 320 300 sleep 0.3 \\
    mousemove 400 300 sleep 0.3 mousemove 470 300 sleep 0.3 mouseup 1
  sleep 1
%s
fi
sleep 1
"""
_DRAG = """  xdotool mousemove %s sleep 0.3 mousedown 1 sleep 0.3 mousemove %s sleep 0.3 mouseup 1
  sleep 1"""


def screenshot(path, delay=2.0, place_window=False, drags=(), trim=False):
    """The whole screen saved to `path` (xwd, ImageMagick's convert), `delay` seconds from
    now, in the background: the click script keeps the GUI's event loop running meanwhile,
    so what the last step changed is drawn. `place_window`: the window first placed and
    its left docks widened (the layout of the docs' pictures of the Properties panel);
    `drags`: then each (from, to) mouse drag, "x y" pixel positions in that layout (e.g. a
    splitter moved); `trim`: the screen less its empty (black) margin, the main window."""
    script = "sleep %g\n" % delay
    if place_window:
        script += _PLACE_WINDOW % "\n".join(_DRAG % drag for drag in drags)
    script += "xwd -root -silent | convert xwd:- %s'%s'\n" % ("-trim +repage " if trim else "",
                                                              path)
    subprocess.Popen(["sh", "-c", script])
