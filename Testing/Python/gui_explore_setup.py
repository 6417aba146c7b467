"""GUI test of a first exploration by clicks, part 1 (run by `paraview --script=` before
gui_explore_click.xml plays the clicks): File > Open of ch2, aal and brodmann (one file
dialog), Explore Multichannel, a drag of a widget sphere in the reduced domain, a probe
click in the volume, Edit > Undo twice.

The three brain files are linked into $MCV_OUTPUT_DIR/gui_explore/ so that the recorded
file dialog names them as $PARAVIEW_TEST_ROOT/gui_explore/... on any machine. Nothing is
opened here. What happens is recorded into $MCV_GUI_STATE for gui_explore_check.py:
- after the exploration (the GUI button's last step, wrapped): the pipeline (names,
  types), every render view with what it shows, the layout, the widgets, the camera and
  the best direction; then the domain view's camera is pointed at one widget's centre
  (so the recorded drag from the view's middle grabs a sphere whatever the seeding gave);
- every change of the widgets, every push and undo of the undo stack with a snapshot of
  the pipeline at that moment;
- the probe's answer (probe_at_pixel wrapped), and a screenshot of the whole window 2.5 s
  after it (the domain view's camera reset to the whole domain first):
  gui_explore_window.png."""
import os

from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce
import multichannel_explorer.exploration as exploration
import gui_setup as G

folder = os.path.join(G.output_dir(), "gui_explore")
os.makedirs(folder, exist_ok=True)
window_png = G.removed(os.path.join(G.output_dir(), "gui_explore_window.png"))
state = G.State("explore", files=[], changes=[], undo=[], probes=[], screenshot=window_png)
save = state.save
for name in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"):
    source, link = G.data_path(name), G.removed(os.path.join(folder, name))
    if os.path.exists(source):
        os.symlink(os.path.abspath(source), link)
        state["files"].append(name)


def camera(view):
    return {"position": [float(v) for v in view.CameraPosition],
            "focal_point": [float(v) for v in view.CameraFocalPoint],
            "view_up": [float(v) for v in view.CameraViewUp]}


def producers(proxy):
    """The vtkSMProxy objects feeding `proxy`'s Input (none for a reader)."""
    prop = proxy.SMProxy.GetProperty("Input")
    return [prop.GetProxy(i) for i in range(prop.GetNumberOfProxies())] if prop else []


def snapshot():
    """The pipeline and the views as the user sees them."""
    pxm = servermanager.ProxyManager()
    sources = {}
    for (name, _), proxy in GetSources().items():
        inputs = [pxm.GetProxyName("sources", producer) for producer in producers(proxy)]
        sources[name] = {"type": proxy.GetXMLName(), "inputs": inputs}
    views = []
    for view in GetViews():
        shown = []
        for rep in view.Representations:
            if rep.GetProperty("Input") is None or not rep.Visibility:
                continue
            kind = rep.GetProperty("Representation")
            shown.append({"source": pxm.GetProxyName("sources", producers(rep)[0]),
                          "representation": kind.SMProperty.GetElement(0) if kind else "",
                          "widgets": len(rep.GaussianWidgets) // 8
                          if rep.GetProperty("GaussianWidgets") is not None else None})
        layout = GetLayout(view)
        views.append({"type": view.GetXMLName(), "shown": shown,
                      "layout": pxm.GetProxyName("layouts", layout) if layout else None,
                      "cell": layout.GetViewLocation(view) if layout else None})
    return {"sources": sources, "views": views}


stack = servermanager.vtkSMProxyManager.GetProxyManager().GetUndoStackBuilder().GetUndoStack()


def on_pushed(*unused):
    labels = [stack.GetUndoSetLabel(i) for i in range(min(3, stack.GetNumberOfUndoSets()))]
    state["undo"].append({"event": "pushed", "labels": labels,
                          "changes_so_far": len(state["changes"])})
    save()


def on_undone(*unused):
    exploration_result = exploration.last
    entry = {"event": "undone", "snapshot": snapshot(), "changes_so_far": len(state["changes"]),
             "labels": [stack.GetUndoSetLabel(i)
                        for i in range(min(3, stack.GetNumberOfUndoSets()))]}
    if exploration_result is not None:
        try:
            entry["widgets"] = [float(v) for v in exploration_result.display.GaussianWidgets]
        except Exception as error:  # noqa: BLE001 - the display is gone: say so
            entry["widgets_error"] = str(error)
    state["undo"].append(entry)
    save()


stack.AddObserver(1987, on_pushed)  # vtkSMUndoStack::PushUndoSetEvent
stack.AddObserver("EndEvent", on_undone)  # after an undo (or redo) completed

_step = exploration._gui_step


def gui_step(*args, **kwargs):
    text = _step(*args, **kwargs)
    state.setdefault("steps", []).append(text)
    result = exploration.last if exploration.done and not exploration.failed else None
    if result is not None and "explored" not in state:
        volume_view, domain_view = result.volume_view, result.domain_view
        best = result.viewpoint
        state["explored"] = {
            "text": text, "name": result.name, "snapshot": snapshot(),
            "camera": camera(volume_view),
            "direction": [float(v) for v in best.direction] if best.valid else None,
            "widgets": [float(v) for v in result.display.GaussianWidgets],
            "active_source": servermanager.ProxyManager().GetProxyName(
                "sources", GetActiveSource()),
            "volume_view_is_active": GetActiveView().SMProxy is volume_view.SMProxy}
        # Point the domain view at the smallest widget's centre from +z (a fixed test
        # rig: the drag in the click script starts at the view's middle).
        values = state["explored"]["widgets"]
        sizes = [values[i + 3] for i in range(0, len(values), 8)]
        k = sizes.index(min(sizes))
        centre = values[8 * k:8 * k + 3]
        distance = 6 * max(sizes) + 4 * max(abs(c) for c in centre) + 1
        domain_view.CameraFocalPoint = centre
        domain_view.CameraPosition = [centre[0], centre[1], centre[2] + distance]
        domain_view.CameraViewUp = [0, 1, 0]
        domain_view.CameraParallelProjection = 1
        domain_view.CameraParallelScale = 3 * sizes[k]
        Render(domain_view)
        state["explored"]["target_widget"] = k
        result.display.GetProperty("GaussianWidgets").SMProperty.AddObserver(
            "ModifiedEvent", lambda *unused: state["changes"].append(
                [float(v) for v in result.display.GaussianWidgets]) or save())
    save()
    return text


exploration._gui_step = gui_step

_probe_at_pixel = mce.probe_at_pixel


def probe_at_pixel(view, x, y, *args, **kwargs):
    hit = _probe_at_pixel(view, x, y, *args, **kwargs)
    state["probes"].append({"pixel": [x, y], "point_id": hit.point_id if hit else None,
                            "coordinates": list(hit.coordinates) if hit else None})
    save()
    # The picture for the user guide shows the whole reduced domain, as Explore left it
    # (the drag's camera above was a test rig).
    if exploration.last is not None:
        ResetCamera(exploration.last.domain_view)
        Render(exploration.last.domain_view)
    G.screenshot(window_png, delay=2.5, trim=True)
    return hit


mce.probe_at_pixel = probe_at_pixel
save()
