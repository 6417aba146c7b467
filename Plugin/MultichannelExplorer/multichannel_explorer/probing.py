"""Probing: one voxel of a "Gaussian TF Volume" read back (index, world position, reduced
coordinates, channels, Features, Foreground) and marked in the reduced domain beside it;
a new Gaussian widget placed at probed coordinates ("add widget here"). The voxel under a
pixel of the volume view (the GUI's Probe toggle) is in picking.py.
"""

import numbers

from ._common import _TracedProperties, _find_filter, _simple, _view_time
from ._voxels import (_NOT_CHANNELS, _Grid, _coordinate_range, _find_or_create,
                      _views_showing, _voxel_values)
from .transfer_function import (_coordinates_name, _domain_size, _gaussian_tf_display,
                                _set_widget_state, _source_and_display, _widget_state,
                                _widget_values, check_widget_values)
from .viewpoint import ViewpointResult

__all__ = [
    "probe",
    "add_widget_at",
    "palette_color",
    "presentable_opacity",
    "PROBE_MARKER",
]

PROBE_MARKER = "ProbeMarker"           # sphere at the probed coordinates, domain view
PROBE_VOXEL_MARKER = "ProbeVoxelMarker"  # sphere at the probed voxel, volume view

# ColorBrewer Set1 without its grey: the client's copy of the core's palette
# (Filters/Core/transfer_function/GaussianWidgetFormula.h, kWidgetPalette; widgetColor's
# indices 8-15 are the same colours at 0.6 shade), so widgets added here match the seeded
# ones; pvbatch.test_widget_formula checks that the two agree.
_SET1 = ((0xE4, 0x1A, 0x1C), (0x37, 0x7E, 0xB8), (0x4D, 0xAF, 0x4A), (0x98, 0x4E, 0xA3),
         (0xFF, 0x7F, 0x00), (0xFF, 0xFF, 0x33), (0xA6, 0x56, 0x28), (0xF7, 0x81, 0xBF))


def palette_color(index):
    """The core's widgetColor(index): Set1, then the same colours darker."""
    i = index % (2 * len(_SET1))
    shade = 1.0 if i < len(_SET1) else 0.6
    return [shade * c / 255.0 for c in _SET1[i % len(_SET1)]]


def _unused_color(widgets):
    used = [widgets[w + 4:w + 7] for w in range(0, len(widgets) - 7, 8)]
    for index in range(2 * len(_SET1)):
        rgb = palette_color(index)
        if all(max(abs(a - b) for a, b in zip(rgb, u)) > 2e-3 for u in used):
            return rgb
    return palette_color(len(used))  # every colour taken: cycle on


def _is_int(v):
    return isinstance(v, numbers.Integral) and not isinstance(v, bool)


def _resolve_voxel(grid, voxel, position):
    """0-based (i, j, k) of an index triple of ints, a flat point id, or a world position
    (3 numbers, not all int, or `position`): its nearest voxel."""
    if position is not None:
        return grid.index_at([float(v) for v in position])
    if _is_int(voxel):
        return grid.index_of_id(voxel)
    voxel = list(voxel)
    if len(voxel) != 3:
        raise ValueError("a voxel is (i, j, k), a point id or a world position (x, y, z), "
                         "not %r" % (voxel,))
    if all(_is_int(v) for v in voxel):
        return grid.check_index(voxel)
    return grid.index_at([float(v) for v in voxel])


def _domain_view(source):
    """The render view showing the ReducedDomain of `source` (show_dual_domain's)."""
    domain = _find_filter(source, "ReducedDomain")
    if domain is None:
        return None, None
    views = _views_showing(domain, port=0)
    return domain, (views[0] if views else None)


def _show_marker(name, center, radius, view, color):
    simple = _simple()
    sphere = _find_or_create(name, simple.Sphere)
    with _TracedProperties(sphere):
        sphere.Center = [float(c) for c in center]
        sphere.Radius = float(radius)
        sphere.ThetaResolution = sphere.PhiResolution = 16
    rep = simple.Show(sphere, view)
    with _TracedProperties(rep):
        rep.ColorArrayName = ["POINTS", ""]  # solid colour
        rep.AmbientColor = rep.DiffuseColor = list(color)
    return sphere


def probe(target, voxel=None, view=None, domain_view=None, position=None, mark=True,
          render=True, _grid=None, _fetched=None):
    """Reads one voxel of the volume behind `target` (a "Gaussian TF Volume" display, or
    the volume itself) and marks it in the reduced domain.

    `voxel`: a 0-based index (i, j, k) of ints (counted from the first voxel of the
    whole extent), a flat point id over the whole volume (int; ReducedDomain's VoxelId),
    or a world position (3 numbers, not all ints; or pass `position=`): the nearest voxel
    (a position more than half a voxel outside the volume is an error). The same voxel,
    values and marker in a serial session, under mpiexec pvbatch and on an MPI pvserver. Returns a dict (also
    with attribute access): index, point_id, position (world), coordinates (the voxel's
    ReducedCoordinates, or the display's coordinate array), channels ({name: value(s)}),
    features, foreground (None without a Foreground array), values (every point array),
    labels ({channel: label} for channels with a label table, e.g. AAL's "Precentral_L"
    for value 1: the NIfTI reader attaches the atlas's label file beside it,
    mcvLabelTables.h), display (the volume's "Gaussian TF Volume" display, if any: for
    add_widget_at).

    With `mark` and a domain view (`domain_view`, else the view show_dual_domain made
    for this volume), a sphere named PROBE_MARKER moves to the coordinates there (z = 0
    for 2D coordinates), and one named "ProbeVoxelMarker" to the voxel in `view` (the
    volume's view; default the view showing the display). Both are replaced, not added,
    by the next probe. `render`: render the views with the markers now (the GUI leaves
    that to its own render, after the answer is shown)::

        hit = mce.probe(display, (40, 52, 30))
        print(hit.coordinates, hit.channels, hit.foreground)
    """
    source, display = _source_and_display(target, view)
    if display is None:  # e.g. probed from the domain view: the volume's display elsewhere
        display = next((d for d in (_gaussian_tf_display(source, v)
                                    for v in _views_showing(source)) if d is not None), None)
    if voxel is None and position is None:
        raise ValueError("probe needs a voxel: (i, j, k), a point id or a world position")
    grid = _grid or _Grid(source)
    index = _resolve_voxel(grid, voxel, position)
    name = _coordinates_name(display) if display is not None else "ReducedCoordinates"
    values, tables = _voxel_values(source, grid, index, name, fetched=_fetched)
    if name not in values:
        raise ValueError("the volume has no point array %s (reduced coordinates)" % name)
    coordinates = list(values[name])
    foreground = values.get("Foreground")
    result = ViewpointResult(
        index=tuple(index), point_id=grid.point_id(index), position=grid.position(index),
        coordinates=coordinates,
        channels={k: (v[0] if len(v) == 1 else list(v)) for k, v in values.items()
                  if k not in _NOT_CHANNELS and k != name},
        features=list(values["Features"]) if "Features" in values else None,
        foreground=int(foreground[0]) if foreground is not None else None,
        values=values, marker=None, domain_view=None, display=display,
        labels={channel: tables[channel][int(round(values[channel][0]))]
                for channel in tables if channel in values and len(values[channel]) == 1
                and int(round(values[channel][0])) in tables[channel]})
    if not mark:
        return result

    simple = _simple()
    domain, found_view = _domain_view(source)
    domain_view = domain_view or found_view
    if domain_view is not None:
        span = max(hi - lo for lo, hi in _coordinate_range(source, name)) or 1.0
        center = (coordinates + [0.0, 0.0])[:3]
        result.marker = _show_marker(PROBE_MARKER, center, 0.025 * span, domain_view,
                                     (1.0, 1.0, 1.0))
        result.domain_view = domain_view
        if render:
            simple.Render(domain_view)
    volume_views = [view] if view is not None else _views_showing(source)
    if volume_views and volume_views[0] is not domain_view:
        b = grid.bounds()
        diagonal = sum((b[2 * a + 1] - b[2 * a]) ** 2 for a in range(3)) ** 0.5
        # Visible at the volume's scale without hiding the voxels around it.
        radius = max(0.01 * diagonal, 0.5 * min(grid.spacing))
        _show_marker(PROBE_VOXEL_MARKER, result.position, radius, volume_views[0],
                     (1.0, 1.0, 1.0))
        if render:
            simple.Render(volume_views[0])
    return result


# The peak opacity a new widget gets at most (a small structure's).
ADDED_WIDGET_PEAK = 0.5


def presentable_opacity(source, coords, sigma, peak=ADDED_WIDGET_PEAK, coordinates=None,
                        widgets=None):
    """The peak opacity that lets a widget at `coords` with `sigma` show what lies behind
    it, by the seeding rule (WidgetSeeding.h): its share s of the drawn voxels (the
    ReducedDomain sample's points within its half maximum), the mean length L of a ray
    through them (ReducedDomain's ForegroundRayLength) and its mean Gaussian weight g
    over those points give a = (1 - 0.5^(1 / (s L))) / g, at most `peak` (a widget that
    selects nothing gets `peak`). `widgets`: the display's widgets, which the domain
    filter colours by (it warns of a transparent volume without any). Returns (opacity,
    share)."""
    import math

    from paraview import servermanager
    from .dual_domain import reduced_domain_filter

    props = {"Coordinates": ["POINTS", coordinates]} if coordinates else {}
    if widgets:
        props["GaussianWidgets"] = list(widgets)
    domain = reduced_domain_filter(source, **props)
    domain.UpdatePipeline(_view_time())  # the time step on screen
    domain.UpdatePropertyInformation()
    ray = float(domain.GetProperty("ForegroundRayLength")[0])
    points = servermanager.Fetch(domain).GetPoints()
    centre = (list(coords) + [0.0])[:3]
    limit = 2.0 * math.log(2.0) * sigma * sigma  # half maximum
    weights = []
    for p in range(points.GetNumberOfPoints() if points is not None else 0):
        d2 = sum((a - b) ** 2 for a, b in zip(points.GetPoint(p), centre))
        if d2 <= limit:
            weights.append(math.exp(-d2 / (2.0 * sigma * sigma)))
    total = points.GetNumberOfPoints() if points is not None else 0
    if not weights or not total or ray <= 0:
        return peak, 0.0
    share = float(len(weights)) / total
    mean_weight = sum(weights) / len(weights)
    crossed = share * ray
    per_voxel = 1.0 - 0.5 ** (1.0 / crossed) if crossed > 1 else 0.5
    return min(peak, per_voxel / mean_weight), share


def add_widget_at(target, coords, sigma=None, opacity=None, color=None, view=None, name=None):
    """Appends a Gaussian widget at `coords` (2 or 3 reduced coordinates, or the result of
    probe()) to the GaussianWidgets of `target` (a "Gaussian TF Volume" display, or the
    volume shown as one in `view`): colour the first of the core's palette (ColorBrewer
    Set1, then darker) that no widget of the display has yet, sigma 5% of the largest
    range of the coordinates over the volume, peak opacity `opacity` (default: the one
    that lets what lies behind it show, presentable_opacity, at most 0.5: a widget that
    selects a large class stays a veil instead of washing the picture in its colour).
    Its name (GaussianWidgetNames): `name`, else the atlas label of the probed voxel
    when `coords` is a probe() result with one, else "Widget N". Returns the new widget
    (8 numbers)::

        hit = mce.probe(display, (40, 52, 30))
        mce.add_widget_at(display, hit)        # "add widget here"
    """
    source, display = _source_and_display(target, view)
    if display is None:
        raise ValueError("add_widget_at needs a \"Gaussian TF Volume\" display")
    hit = coords if isinstance(coords, dict) else None
    if hit is not None:
        coords = hit["coordinates"]
    coords = [float(c) for c in coords]
    if len(coords) not in (2, 3):
        raise ValueError("widget coordinates are 2 or 3 numbers, not %r" % (coords,))
    if sigma is None:
        ranges = _coordinate_range(source, _coordinates_name(display))
        sigma = 0.05 * (max(hi - lo for lo, hi in ranges) or 1.0)
    size = _domain_size(source, _coordinates_name(display))
    widgets = _widget_values(display)
    rgb = list(color) if color is not None else _unused_color(widgets)
    if opacity is None:
        opacity, _ = presentable_opacity(source, coords, float(sigma),
                                         coordinates=_coordinates_name(display),
                                         widgets=widgets or (coords + [0.0])[:3] +
                                         [float(sigma)] + [float(c) for c in rgb] +
                                         [ADDED_WIDGET_PEAK])
    widget = (coords + [0.0])[:3] + [float(sigma)] + [float(c) for c in rgb] + [float(opacity)]
    check_widget_values(widget, "add_widget_at", size, first=len(widgets) // 8)
    values = widgets + widget
    count = len(values) // 8
    if name is None:
        labels = (hit.get("labels") or {}) if hit is not None else {}
        name = sorted(labels.values())[0] if labels else "Widget %d" % count
    _, hidden, names = _widget_state(display)
    names = (names + [""] * count)[:count - 1] + [str(name)]
    _set_widget_state(display, values, hidden + [-1.0], names)
    return widget
