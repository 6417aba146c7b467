"""GUI test of the "Probe" toggle and the "Brush Selection" button, part 1 (run by
`paraview --script=` before gui_probe_click.xml switches Probe on, clicks the middle of the
volume view, selects domain points with a rubber band and clicks Brush Selection).

A synthetic volume whose ReducedCoordinates are known (0.1 x, 0.1 y, 0.1 z of the voxel
position) is shown as a Gaussian TF Volume (one widget opaque everywhere) beside its dual
domain, the volume view looking down -z in parallel projection: the click at the view's
centre must probe the top voxel of the centre column, a click on a point of the domain
cloud that point's voxel. probe_at_pixel and brush are wrapped
(the package-level names the buttons call) to record what they returned, the expected
answers computed here from the data, and a screenshot of the whole window (xwd) a moment
later, once the label is shown."""
import os

from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce
import gui_setup as G

out = G.output_dir()

wavelet = Wavelet(WholeExtent=[-10, 10, -10, 10, -6, 6])
coords = Calculator(Input=wavelet, ResultArrayName="ReducedCoordinates", ResultArrayType="Float",
                    Function="0.1*coords")
volume = Calculator(Input=coords, ResultArrayName="Foreground", ResultArrayType="Unsigned Char",
                    Function="1")
volume.UpdatePipeline()
view = GetActiveViewOrCreate("RenderView")
display = mce.show_gaussian_tf(volume, view, widgets=[0, 0, 0, 50.0, 0.9, 0.6, 0.2, 1.0])
dual = mce.show_dual_domain(display, view, sample_size=100000)
for v, data in ((view, volume), (dual.domain_view, dual.filter)):
    Render(v)  # the first render resets the camera: set ours after it
    b = data.GetDataInformation().GetBounds()
    c = [(b[2 * a] + b[2 * a + 1]) / 2.0 for a in range(3)]
    v.CameraFocalPoint = c
    v.CameraPosition = [c[0], c[1], c[2] + 4 * (b[5] - b[4] + b[1] - b[0])]
    v.CameraViewUp = [0, 1, 0]
    v.CameraParallelProjection = 1
    v.CameraParallelScale = 0.6 * max(b[1] - b[0], b[3] - b[2])
    Render(v)
# gui_probe_click.xml clicks the domain view at (0.6043, 0.5408) of its size (from its top
# left) for the cloud point (0.2, -0.1): the camera's centre is placed so that this point
# is drawn there whatever the view's aspect (parallel projection: 2 * scale / height units
# per pixel).
domain_view = dual.domain_view
width, height = [int(n) for n in domain_view.ViewSize]
scale = float(domain_view.CameraParallelScale)
centre = [0.2 - (0.6043 - 0.5) * width * 2 * scale / height, -0.1 + (0.5408 - 0.5) * 2 * scale]
focal_z = float(domain_view.CameraFocalPoint[2])
z = float(domain_view.CameraPosition[2])
domain_view.CameraFocalPoint = [centre[0], centre[1], focal_z]
domain_view.CameraPosition = [centre[0], centre[1], z]
Render(domain_view)
SetActiveView(view)
SetActiveSource(volume)
state = G.State("probe", events=[])
save = state.save


def whole_window(name):
    """A screenshot of the whole screen 2 s from now (the label appears after the helper
    returns); the click script pauses for it."""
    G.screenshot(os.path.join(out, name))


_probe_at_pixel, _brush = mce.probe_at_pixel, mce.brush


def probe_at_pixel(v, x, y, *args, **kwargs):
    hit = _probe_at_pixel(v, x, y, *args, **kwargs)
    # Expected: the voxel whose column projects nearest to the pixel, the top one (+z).
    full = servermanager.Fetch(volume)
    ren = v.GetRenderer()
    best, best_d = None, None
    dims = full.GetDimensions()
    for pid in range(dims[0] * dims[1] * (dims[2] - 1), full.GetNumberOfPoints()):
        ren.SetWorldPoint(*(list(full.GetPoint(pid)) + [1.0]))
        ren.WorldToDisplay()
        px, py, _ = ren.GetDisplayPoint()
        d = (px - x) ** 2 + (py - y) ** 2
        if best_d is None or d < best_d:
            best, best_d = pid, d
    marker = FindSource(mce.PROBE_MARKER)
    state["events"].append({
        "event": "probe", "pixel": [x, y], "view_size": [int(s) for s in v.ViewSize],
        "point_id": hit.point_id if hit else None,
        "coordinates": list(hit.coordinates) if hit else None,
        "expected_id": best,
        "expected_coordinates": list(full.GetPointData().GetArray("ReducedCoordinates")
                                     .GetTuple3(best)),
        "marker": [float(c) for c in marker.Center] if marker else None})
    save()
    whole_window("gui_probe_window.png")
    return hit


_probe_domain_at_pixel = mce.probe_domain_at_pixel


def probe_domain_at_pixel(v, x, y, *args, **kwargs):
    hit = _probe_domain_at_pixel(v, x, y, *args, **kwargs)
    # Expected: of the cloud points within 3 pixels of (x, y), the nearest the camera (+z).
    cloud = servermanager.Fetch(dual.filter)
    ids = cloud.GetPointData().GetArray("VoxelId")
    ren = v.GetRenderer()
    near = []
    for p in range(cloud.GetNumberOfPoints()):
        ren.SetWorldPoint(*(list(cloud.GetPoint(p)) + [1.0]))
        ren.WorldToDisplay()
        px, py, _ = ren.GetDisplayPoint()
        if max(abs(px - x), abs(py - y)) <= 3:
            near.append(p)
    front = max(near, key=lambda p: cloud.GetPoint(p)[2]) if near else None
    marker = FindSource(mce.PROBE_MARKER)
    state["events"].append({
        "event": "probe_domain", "pixel": [x, y], "point_id": hit.point_id if hit else None,
        "expected_id": int(ids.GetValue(front)) if front is not None else None,
        "coordinates": list(hit.coordinates) if hit else None,
        "marker": [float(c) for c in marker.Center] if marker else None})
    save()
    whole_window("gui_probe_domain_window.png")
    return hit


_add_widget_at = mce.add_widget_at


def add_widget_at(target, coords, *args, **kwargs):
    before = [float(v) for v in target.GaussianWidgets]
    widget = _add_widget_at(target, coords, *args, **kwargs)
    state["events"].append({
        "event": "add_widget", "before": before, "widget": list(widget),
        "after": [float(v) for v in display.GaussianWidgets],
        "coordinates": list(coords["coordinates"] if isinstance(coords, dict) else coords),
        "palette": [mce.palette_color(i) for i in range(16)]})
    save()
    return widget


def brush(*args, **kwargs):
    count = _brush(*args, **kwargs)
    # Expected: the VoxelIds of the domain points in ParaView's selection of ReducedDomain.
    selection = dual.filter.SMProxy.GetSelectionInput(0)
    expected = []
    if selection is not None:
        picked = servermanager.Fetch(servermanager.filters.ExtractSelection(
            Input=dual.filter, Selection=servermanager._getPyProxy(selection)))
        ids = picked.GetPointData().GetArray("VoxelId")
        expected = sorted(int(ids.GetValue(p)) for p in range(ids.GetNumberOfTuples()))
    shown = servermanager.Fetch(FindSource(mce.BRUSHED_VOXELS))
    original = shown.GetPointData().GetArray("VoxelId")
    state["events"].append({
        "event": "brush", "count": count, "expected": expected,
        "highlighted": sorted(int(original.GetValue(p))
                              for p in range(original.GetNumberOfTuples())) if original else []})
    save()
    whole_window("gui_brush_window.png")
    return count


mce.probe_at_pixel, mce.brush = probe_at_pixel, brush
mce.probe_domain_at_pixel, mce.add_widget_at = probe_domain_at_pixel, add_widget_at
save()
