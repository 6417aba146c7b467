"""GUI test of the Gaussian widget handles, part 3 (run by test_gui.sh with the state file
and paraview's exit status). gui_handles_click.xml dragged widget 1's handle in the
domain view from the view's middle to (0.58, 0.45) of the view, then shift+dragged it up
to (0.58, 0.40), then undid both. Expected, from the domain view's parallel camera
(ParallelScale S = 12 half-heights, looking down -z) and its size W x H: QtTesting puts
the mouse at (int(fx W), int(fy H)) (Qt's y downwards); one pixel is 2 S / H domain
units; the drag moves the centre by the mouse's displacement (x right, y up, z kept);
the shift+drag scales sigma by the upward distance (vtkSphereWidget2's scaling:
sigma + |motion| per move upwards); each drag is one undo set; the GaussianWidgets
property changed at every mouse move (the volume recolours while dragging)."""
import json
import os

from gui_checks import arguments, check, fails, finish  # noqa: E402,F401

path, rc = arguments()
TOL = 1e-3  # domain units; a pixel is ~0.05 here


def close(a, b, tol=TOL):
    return all(abs(x - y) <= tol for x, y in zip(a, b)) and len(a) == len(b)


def pixel(fraction, size):
    return int(fraction * size)  # as pqQVTKWidgetEventPlayer


check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
try:
    state = json.load(open(path))
except Exception as e:  # noqa: BLE001
    state = {}
    check(False, "state file %s readable (%s)" % (path, e))
initial = state.get("initial", [])
changes = state.get("changes", [])
undo = state.get("undo", [])
check(len(initial) == 24, "3 widgets at the start")


def values_when(label):
    """GaussianWidgets when the undo set `label` was pushed (top of the stack)."""
    for entry in undo:
        if entry["labels"] and entry["labels"][0] == label and entry["changes_so_far"]:
            return changes[entry["changes_so_far"] - 1], entry["changes_so_far"]
    return None, 0


moved, n_move = values_when("Move Gaussian Widget 1")
if check(moved is not None, "a drag on widget 1's handle made one undo set "
                            "'Move Gaussian Widget 1'"):
    w, h = moved["view_size"]
    s = moved["parallel_scale"]
    unit = 2.0 * s / h
    check(moved["parallel"] == 1 and close(moved["position"], [0, 0, 50]) and
          close(moved["focal_point"], [0, 0, 0]) and abs(s - 12) < 1e-9,
          "... the domain view kept the known parallel camera (%dx%d pixels, %.4f units "
          "per pixel)" % (w, h, unit))
    dx_px = pixel(0.58, w) - pixel(0.5, w)
    dy_px = pixel(0.5, h) - pixel(0.45, h)  # Qt's y grows downwards
    expected = [initial[0] + dx_px * unit, initial[1] + dy_px * unit, initial[2]]
    got = moved["values"][:3]
    check(close(got, expected),
          "... its centre moved by (%d, %d) pixels = (%.4f, %.4f) domain units: "
          "(%.4f, %.4f, %.4f), expected (%.4f, %.4f, %.4f)"
          % ((dx_px, dy_px, dx_px * unit, dy_px * unit) + tuple(got) + tuple(expected)))
    check(close(moved["values"][3:], initial[3:], 1e-12),
          "... sigma, colour, opacity and the other widgets unchanged")
    check(n_move >= 3, "... GaussianWidgets set at every mouse move (%d times: the volume "
                       "recoloured while dragging)" % n_move)

resized, n_resize = values_when("Resize Gaussian Widget 1")
if moved is not None and check(resized is not None,
                               "shift+drag on the handle made one undo set "
                               "'Resize Gaussian Widget 1'"):
    w, h = resized["view_size"]
    unit = 2.0 * resized["parallel_scale"] / h
    up_px = pixel(0.45, h) - pixel(0.40, h)
    expected_sigma = moved["values"][3] + up_px * unit
    check(abs(resized["values"][3] - expected_sigma) <= TOL,
          "... sigma grew by the %d pixels upwards: %.4f -> %.4f (expected %.4f)"
          % (up_px, moved["values"][3], resized["values"][3], expected_sigma))
    rest = resized["values"][:3] + resized["values"][4:]
    check(close(rest, moved["values"][:3] + moved["values"][4:], 1e-12),
          "... the centre and everything else unchanged")
    top = [e["labels"][:2] for e in undo if e["labels"] and
           e["labels"][0] == "Resize Gaussian Widget 1"]
    check(bool(top) and top[0][1:] == ["Move Gaussian Widget 1"],
          "... on the undo stack above the move (%s)" % (top[0] if top else None))

final = changes[-1]["values"] if changes else None
check(final is not None and close(final, initial, 1e-12),
      "two Undo clicks restored the initial widgets")
shot = state.get("screenshot")
check(bool(shot) and os.path.exists(shot) and os.path.getsize(shot) > 10000,
      "whole-window screenshot after the drags: %s" % shot)
finish("gui_handles")
