"""The best viewpoint: the BestViewpoint filter on a source, the camera turned (at once or
in rendered steps) to the best or worst view, and the camera following the widgets of a
Gaussian TF display.
"""

import math

from ._common import (_FILTER_XML_NAME, _Follower, _filter, _find_filter, _followers,
                      _is_representation, _simple, _warn)
from .images import _render_entropy
from .transfer_function import (GAUSSIAN_TF_REPRESENTATION, _coordinates_name,
                                _gaussian_tf_display, _volume_display, _widget_values)

__all__ = [
    "ViewpointResult",
    "best_viewpoint_filter",
    "apply_best_viewpoint",
    "set_camera_direction",
    "turn_camera",
    "follow_best_viewpoint",
    "stop_following",
]


class ViewpointResult(dict):
    """What apply_best_viewpoint did: a dict whose keys are also attributes.

    Keys: ``direction`` (unit vector the camera looks along), ``which``, ``best``,
    ``worst``, ``view_up``, ``eigenvalues`` (descending, sum 1), ``center`` (focal
    point), ``valid``, ``device``, ``filter`` (the BestViewpoint proxy), ``entropies``
    ({"+": bits, "-": bits} when disambiguate=True, else None), ``sign`` (+1 or -1
    relative to the filter's direction), ``camera_position``.
    """

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name)


def best_viewpoint_filter(source, view=None, **filter_properties):
    """Creates (or reuses) the BestViewpoint filter on `source`, sets its properties,
    updates it and its information properties, and returns it.

    When `source` is shown as a Volume in `view` and neither OpacityFunction nor
    Channels is given, the filter follows that display: its Scalar Opacity Function and
    its colouring array. When it is shown as a "Gaussian TF Volume", the filter takes
    the opacity of that display's Gaussian widgets (OpacitySource = Representation).
    The active source is left as it was.
    """
    if source is None:
        raise ValueError("best_viewpoint_filter: no source given")
    simple = _simple()
    active = simple.GetActiveSource()
    bvp = _find_filter(source)
    if bvp is None:
        bvp = _filter(_FILTER_XML_NAME)(Input=source)
        if active is not None:
            simple.SetActiveSource(active)

    rep = _volume_display(source, view)
    gaussian = _gaussian_tf_display(source, view)
    if gaussian is not None and "OpacitySource" not in filter_properties:
        # The best view of what the multichannel transfer function shows.
        filter_properties["OpacitySource"] = "Representation"
        filter_properties.setdefault("GaussianWidgets", _widget_values(gaussian))
        filter_properties.setdefault("WidgetCoordinates", _coordinates_name(gaussian))
    if rep is not None:
        if "OpacityFunction" not in filter_properties:
            filter_properties["OpacityFunction"] = rep.ScalarOpacityFunction
        if "Channels" not in filter_properties:
            try:
                association, name = rep.ColorArrayName[0], rep.ColorArrayName[1]
            except (IndexError, TypeError):
                association, name = None, None
            if name and association == "POINTS":
                filter_properties["Channels"] = [name]
    for key, value in filter_properties.items():
        if key == "OpacityFunction" and value is None:
            bvp.GetProperty("OpacityFunction").SetData(None)
            continue
        setattr(bvp, key, value)
    bvp.UpdatePipeline()
    bvp.UpdatePropertyInformation()
    return bvp


def _vec(proxy, name):
    return [float(x) for x in proxy.GetPropertyValue(name)]


def set_camera_direction(view, center, direction, view_up, fill=True):
    """Points the camera of `view` along `direction` (from the camera towards `center`),
    with `view_up`, keeping the current distance; then resets the camera so the visible
    data fills the view (the direction is kept)."""
    simple = _simple()
    focal = [float(c) for c in center]
    pos = [float(p) for p in view.CameraPosition]
    old_focal = [float(p) for p in view.CameraFocalPoint]
    distance = math.sqrt(sum((p - f) ** 2 for p, f in zip(pos, old_focal)))
    if not distance > 1e-9:
        distance = 1.0
    view.CameraFocalPoint = focal
    view.CameraPosition = [f - d * distance for f, d in zip(focal, direction)]
    view.CameraViewUp = [float(u) for u in view_up]
    if fill:
        try:
            view.ResetCamera(True)  # closest fit, direction kept
        except TypeError:
            view.ResetCamera()
        # Reset moves the focal point to the centre of the visible bounds; keep ours
        # (the volume's centre) at the same distance.
        pos = [float(p) for p in view.CameraPosition]
        f2 = [float(p) for p in view.CameraFocalPoint]
        distance = math.sqrt(sum((p - f) ** 2 for p, f in zip(pos, f2)))
        view.CameraFocalPoint = focal
        view.CameraPosition = [f - d * distance for f, d in zip(focal, direction)]
        view.CameraViewUp = [float(u) for u in view_up]
    simple.Render(view)


def apply_best_viewpoint(source, view=None, which="best", disambiguate=False,
                         **filter_properties):
    """Turns the camera of `view` (default: the active view) to the best (or worst) view
    of `source`, a volume (image data).

    * Creates or updates a BestViewpoint filter on `source` with `filter_properties`
      (e.g. NumberOfInterestPoints=1024, Channels=["a", "b"], Method="AreaMaximizing").
      When `source` is shown as a Volume in `view`, the filter uses that display's
      Scalar Opacity Function (and colouring array) unless they are given.
    * which="best": the camera looks along v3 (least variance of the interest points);
      which="worst": along v1. View-up is v2 in both cases.
    * The focal point is the volume's centre; the camera is then reset (direction kept)
      so the data fills the view, and the view is rendered.
    * disambiguate=True: v and -v are equally good by variance; both are rendered and
      the one whose image has the higher luminance entropy is kept.

    Returns a ViewpointResult (dict with attribute access). When no direction could be
    found (flat or constant volume), a warning is given, the camera is left as it was
    and result.valid is False.
    """
    simple = _simple()
    if which not in ("best", "worst"):
        raise ValueError('which must be "best" or "worst", not %r' % (which,))
    if source is None:
        raise ValueError("apply_best_viewpoint: no source given")
    if view is None:
        view = simple.GetActiveViewOrCreate("RenderView")
    if not hasattr(view, "CameraPosition"):
        raise ValueError("apply_best_viewpoint needs a render view, not %s"
                         % view.GetXMLName())

    bvp = best_viewpoint_filter(source, view, **filter_properties)
    best = _vec(bvp, "BestViewDirection")
    worst = _vec(bvp, "WorstViewDirection")
    up = _vec(bvp, "ViewUp")
    eig = _vec(bvp, "EigenvalueSpectrum")
    center = _vec(bvp, "DataCenter")
    valid = bool(bvp.GetPropertyValue("ViewValid"))
    device = bvp.GetPropertyValue("DeviceUsed")
    direction = best if which == "best" else worst
    result = ViewpointResult(
        direction=direction, which=which, best=best, worst=worst, view_up=up,
        eigenvalues=eig, center=center, valid=valid, device=device, filter=bvp,
        entropies=None, sign=1, camera_position=None)
    if not valid or sum(d * d for d in direction) < 0.5:
        _warn("no %s view direction for this volume (flat or constant opacity?): "
              "the camera was not changed" % which)
        result["valid"] = False
        return result

    sign = 1
    if disambiguate:
        entropies = {}
        for s, key in ((1, "+"), (-1, "-")):
            set_camera_direction(view, center, [s * d for d in direction], up)
            entropies[key] = _render_entropy(view)
        result["entropies"] = entropies
        sign = 1 if entropies["+"] >= entropies["-"] else -1
    final = [sign * d for d in direction]
    set_camera_direction(view, center, final, up)
    result["direction"] = final
    result["sign"] = sign
    result["camera_position"] = [float(p) for p in view.CameraPosition]
    return result


def _normalized(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v] if n > 0 else list(v)


def _slerp(a, b, t):
    """Unit vector a fraction t of the way from unit vector a to b along the great circle."""
    dot = max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b))))
    angle = math.acos(dot)
    if angle < 1e-6:
        return list(b)
    if math.pi - angle < 1e-6:  # opposite: turn through any perpendicular
        perp = _normalized([a[1], -a[0], 0.0] if abs(a[2]) < 0.9 else [0.0, a[2], -a[1]])
        return _normalized([math.cos(t * math.pi) * x + math.sin(t * math.pi) * y
                            for x, y in zip(a, perp)])
    s = math.sin(angle)
    return [(math.sin((1 - t) * angle) * x + math.sin(t * angle) * y) / s
            for x, y in zip(a, b)]


def turn_camera(view, center, direction, view_up, frames=10):
    """Turns the camera of `view` to look along `direction` at `center` in `frames`
    rendered steps (great-circle interpolation of the direction and the view-up), then
    fits the data in the view. frames <= 1: at once."""
    position = [float(p) for p in view.CameraPosition]
    focal = [float(p) for p in view.CameraFocalPoint]
    start = _normalized([f - p for f, p in zip(focal, position)])
    start_up = _normalized([float(u) for u in view.CameraViewUp])
    goal, goal_up = _normalized(direction), _normalized(view_up)
    for i in range(1, max(1, int(frames))):
        t = float(i) / frames
        d = _slerp(start, goal, t)
        up = _slerp(start_up, goal_up, t)
        # Keep view-up perpendicular to the direction.
        dot = sum(x * y for x, y in zip(up, d))
        up = _normalized([u - dot * x for u, x in zip(up, d)])
        set_camera_direction(view, center, d, up, fill=False)
    set_camera_direction(view, center, goal, goal_up)


def follow_best_viewpoint(display, view=None, frames=10, which="best", **filter_properties):
    """Keeps the camera of `view` on the best view of what a "Gaussian TF Volume"
    `display` shows: now, and after every change of its GaussianWidgets the best
    viewpoint is recomputed from the widgets' opacity and the camera turns there in
    `frames` rendered steps. Returns an object with .stop() (also stop_following())."""
    simple = _simple()
    if view is None:
        view = simple.GetActiveView()
    if not _is_representation(display):
        source = display
        display = _gaussian_tf_display(source, view)
        if display is None:
            raise ValueError("follow_best_viewpoint needs a display of type %r in the view"
                             % GAUSSIAN_TF_REPRESENTATION)
    source = display.Input
    state = {"result": None}

    def update():
        props = dict(filter_properties)
        props.update(OpacitySource="Representation", GaussianWidgets=_widget_values(display),
                     WidgetCoordinates=_coordinates_name(display))
        bvp = best_viewpoint_filter(source, view, **props)
        direction = _vec(bvp, "BestViewDirection" if which == "best" else "WorstViewDirection")
        if not bvp.GetPropertyValue("ViewValid") or sum(d * d for d in direction) < 0.5:
            _warn("follow_best_viewpoint: no %s view for these widgets; the camera stays"
                  % which)
            return
        # Of +v and -v, the one nearer the current camera: the smallest turn.
        position = [float(p) for p in view.CameraPosition]
        focal = [float(p) for p in view.CameraFocalPoint]
        current = [f - p for f, p in zip(focal, position)]
        if sum(c * d for c, d in zip(current, direction)) < 0:
            direction = [-d for d in direction]
        turn_camera(view, _vec(bvp, "DataCenter"), direction, _vec(bvp, "ViewUp"), frames)
        state["result"] = ViewpointResult(direction=direction, filter=bvp, which=which,
                                          eigenvalues=_vec(bvp, "EigenvalueSpectrum"))

    follower = _Follower(display, "GaussianWidgets", update)
    _followers.append(follower)
    update()
    follower.state = state
    return follower


def stop_following():
    """Ends every follow_best_viewpoint / show_dual_domain observer."""
    while _followers:
        follower = _followers.pop()
        if follower is not None:
            follower.stop()
