"""GUI test of the "Follow Best Viewpoint" toggle and the "Seed Gaussian Widgets" button,
part 1 (run by `paraview --script=` before gui_follow_click.xml switches the toggle on and
clicks the seed button). A synthetic volume whose ReducedCoordinates are the voxel
positions is shown as a Gaussian TF Volume with 5 widgets on a plane; the helpers the
buttons call (follow_best_viewpoint, auto_widgets) are wrapped so that what they did is
recorded into $MCV_GUI_STATE, with the camera of every render while the seed button's
widgets turn it. gui_follow_check.py checks it."""
import os

from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce
import gui_setup as G

out = G.output_dir()

wavelet = Wavelet(WholeExtent=[-20, 20, -20, 20, -20, 20])
coords = Calculator(Input=wavelet, Function="coords", ResultArrayName="ReducedCoordinates",
                    ResultArrayType="Float")
view = GetActiveViewOrCreate("RenderView")
# 5 widgets on the plane z = 0 (normal +z): the best view looks along z.
widgets = []
for cx, cy in ((0, 0), (-9, 0), (9, 0), (0, -9), (0, 9)):
    widgets += [cx, cy, 0, 2.5, 1, 0.4, 0.1, 1]
display = mce.show_gaussian_tf(coords, view, widgets=widgets)
view.CameraPosition = [60, 20, 10]  # not along z
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 0, 1]
Render(view)
SetActiveSource(coords)
state = G.State("follow", events=[])
save = state.save


def camera():
    p = [float(x) for x in view.CameraPosition]
    f = [float(x) for x in view.CameraFocalPoint]
    return [b - a for a, b in zip(p, f)]


# Every render's camera (direction, view-up): the follower's turn must be animated.
path = []
_camera = view.GetActiveCamera()
view.GetRenderWindow().AddObserver("EndEvent", lambda *unused: path.append(
    [list(_camera.GetDirectionOfProjection()), list(_camera.GetViewUp())]))

_follow, _auto = mce.follow_best_viewpoint, mce.auto_widgets


def follow(*args, **kwargs):
    follower = _follow(*args, **kwargs)
    result = follower.state["result"]
    state["events"].append({"event": "follow", "camera": camera(),
                            "best": list(result.direction) if result else None})
    save()
    return follower


def auto(*args, **kwargs):
    del path[:]
    before = camera()
    seeded = _auto(*args, **kwargs)  # sets the display's widgets: the follower turns
    bvp = mce._find_filter(coords)
    bvp.UpdatePropertyInformation()
    state["events"].append({
        "event": "seed", "widgets": len(seeded), "display_widgets": len(display.GaussianWidgets),
        "camera": camera(), "opacity_source": str(bvp.GetPropertyValue("OpacitySource")),
        "filter_widgets": [float(v) for v in bvp.GaussianWidgets],
        "display_values": [float(v) for v in display.GaussianWidgets],
        "best": [float(x) for x in bvp.GetPropertyValue("BestViewDirection")],
        "before": before, "path": list(path)})
    SaveScreenshot(os.path.join(out, "gui_after_seed.png"), view)
    save()
    return seeded


mce.follow_best_viewpoint, mce.auto_widgets = follow, auto
save()
