"""The best viewpoint: the BestViewpoint filter on a source, the camera turned (at once or
animated over about half a second) to the best or worst view, and the camera following the
widgets of a Gaussian TF display.
"""

import math
import time

from ._common import (_FILTER_XML_NAME, _Follower, _TracedProperties, _filter, _find_filter, _followers,
                      _is_representation, _simple, _view_time, _warn)
from .images import _render_entropy
from .transfer_function import (GAUSSIAN_TF_REPRESENTATION, WIDGET_FIELDS, _coordinates_name,
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
    point: the middle of the visible voxels once the camera is set, else the volume's
    centre), ``visible_bounds`` (the filter's VisibleBounds), ``valid``,
    ``device``, ``filter`` (the BestViewpoint proxy), ``entropies``
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
    updates it (at the time step `view` shows, else the active view's) and its
    information properties, and returns it.

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
    with _TracedProperties(bvp):  # recorded in a trace being recorded
        for key, value in filter_properties.items():
            if key == "OpacityFunction" and value is None:
                bvp.GetProperty("OpacityFunction").SetData(None)
                continue
            setattr(bvp, key, value)
    bvp.UpdatePipeline(_view_time(view))  # the time step on screen
    bvp.UpdatePropertyInformation()
    return bvp


def _vec(proxy, name):
    return [float(x) for x in proxy.GetPropertyValue(name)]


def _upright(view_up):
    """v2 or -v2, whichever keeps the volume upright: the sign of v2 is arbitrary (PCA),
    and the wrong one shows a head or a cell upside down. Up is the positive side of the
    axis v2 lies closest to: +z (superior in a scan) in a side or front view, +y (anterior,
    as axial images are shown; ParaView's own default up) in a view from above or below."""
    axis = max((2, 1, 0), key=lambda a: abs(view_up[a]))  # a tie goes to z, then y
    return [float(c) for c in view_up] if view_up[axis] >= 0 else [-float(c) for c in view_up]


def _fit_camera(view, points, direction, view_up, margin=1.15, render=True):
    """Points the camera of `view` along `direction` (view-up `view_up`) at the middle of
    `points` (world positions: the visible voxels' support points) and as close as they
    allow: every point inside the view, the widest with `margin` (1.15: 15 %) to spare.
    Perspective: from the view angle and the view's aspect; parallel projection: the
    parallel scale. Renders the view unless render=False (a screenshot that follows renders
    it anyway)."""
    focal, w, distance, u, scale = _fitted_camera(view, points, direction, view_up, margin)
    if scale is not None:
        view.CameraParallelScale = scale
    simple = _simple()
    # paraview.simple resets the camera at the session's first Render: not this one's
    getattr(simple, "_DisableFirstRenderCameraReset", lambda: None)()
    _place_camera(view, focal, w, distance, u)
    if render:
        simple.Render(view)


def _fitted_camera(view, points, direction, view_up, margin=1.15):
    """(focal point, direction, distance, view-up, parallel scale or None) of _fit_camera.
    Where the points would reach under the widget legend in the view's top right corner,
    they are fitted below it instead: the top band of the legend's height is left out."""
    w = _normalized(direction)
    u = _normalized([c - _dot(view_up, w) * d for c, d in zip(view_up, w)])
    r = _cross(w, u)
    frame = [(_dot(p, r), _dot(p, u), _dot(p, w)) for p in points]
    middle = [(min(c[a] for c in frame) + max(c[a] for c in frame)) / 2.0 for a in range(3)]
    rel = [(x - middle[0], y - middle[1], z - middle[2]) for x, y, z in frame]
    width, height = [max(1, int(v)) for v in view.ViewSize]
    aspect = float(width) / height
    size = max(max(abs(x), abs(y), abs(z)) for x, y, z in rel) or 1.0
    # the camera stays in front of every point
    nearest = max(-z for _, _, z in rel) + 0.05 * size
    parallel = bool(view.CameraParallelProjection)
    t = 1.0 if parallel else math.tan(math.radians(float(view.CameraViewAngle)) / 2.0)

    def fit(top):
        """(distance, scale, shift along u) with the top `top` of the view's height left out."""
        reach = [max(abs(y) / (1.0 - top), abs(x) / aspect) for x, y, _ in rel]
        if parallel:
            scale = margin * max(reach)
            return max(nearest, 4 * size), scale, top * scale
        distance = max(max(margin * e / t - z for e, (_, _, z) in zip(reach, rel)), nearest)
        return distance, None, top * distance * t

    distance, scale, shift = fit(0.0)
    legend = _legend_fraction(view)
    if legend is not None and any(_in_corner(x, y, z, distance, scale, t, aspect, legend)
                                  for x, y, z in rel):
        distance, scale, shift = fit(min(legend[1], 0.5))
    middle[1] += shift  # the points sit below the band left out
    focal = [middle[0] * r[i] + middle[1] * u[i] + middle[2] * w[i] for i in range(3)]
    return focal, w, distance, u, scale


def _in_corner(x, y, z, distance, scale, t, aspect, corner):
    """Whether a point (relative to the focal point, camera frame) falls in the top right
    corner of the picture of `corner` = (width, height) fractions of the view."""
    depth = scale if scale is not None else (distance + z) * t
    if depth <= 0:
        return False
    return x / (depth * aspect) >= 1.0 - 2.0 * corner[0] and y / depth >= 1.0 - 2.0 * corner[1]


def _legend_fraction(view):
    """(width, height) of the widget legend in `view`, gap to the corner included, as
    fractions of the view; None when no visible Gaussian TF Volume shows one. Sized as
    vtkGaussianTFVolumeRepresentation::UpdateLegend sizes it: one row per drawn widget (peak
    opacity above 0), rows of 13-20 pixels by the view's height (at most 16 and half the
    view), 0.4 of a row a character plus 2.2 rows for the swatch; the shares' text is not
    known before the render: taken as "  12.3%"."""
    width, height = [max(1, int(v)) for v in view.ViewSize]
    row = min(20.0, max(13.0, float(round(height / 28.0))))
    most = max(2, min(16, int(max(0.0, (height / 2.0 - 8) / row))))
    box = None
    for rep in getattr(view, "Representations", []):
        try:
            if not rep.Visibility or rep.Representation != GAUSSIAN_TF_REPRESENTATION or \
                    not rep.ShowWidgetLegend:
                continue
            names = [str(n) for n in rep.GaussianWidgetNames]
        except AttributeError:
            continue
        values, n = _widget_values(rep), len(WIDGET_FIELDS)
        rows = [names[i] if i < len(names) and names[i] else "Widget %d" % (i + 1)
                for i in range(len(values) // n) if values[i * n + n - 1] > 0]
        if len(rows) > most:
            rows = rows[:most - 1] + ["+ %d more widgets" % (len(rows) - most + 1)]
        if not rows:
            continue
        longest = max(len(" " + name + "  12.3%") for name in rows)
        gap = round(row / 2)
        corner = ((2.2 * row + 0.4 * row * longest + gap) / width,
                  (row * len(rows) + 8.0 + gap) / height)
        box = corner if box is None else (max(box[0], corner[0]), max(box[1], corner[1]))
    return box


def _visible_points(bvp):
    """The BestViewpoint filter's VisibleSupport as points, else the corners of its
    VisibleBounds."""
    flat = [float(v) for v in bvp.GetProperty("VisibleSupport")]
    if len(flat) >= 3:
        return [flat[i:i + 3] for i in range(0, len(flat) - 2, 3)]
    b = _vec(bvp, "VisibleBounds")
    return [[b[(c & 1)], b[2 + ((c >> 1) & 1)], b[4 + ((c >> 2) & 1)]] for c in range(8)]


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
      which="worst": along v1. View-up is v2 in both cases, signed so that the volume is
      upright (towards the positive side of the axis v2 lies closest to).
    * The camera is fitted (direction kept) to the voxels the picture shows (opacity of
      at least 1 %; the filter's VisibleSupport, their silhouette from any direction):
      centred on them, as close as lets every one stay in view with a 15 % margin, and
      below the widget legend of a Gaussian TF Volume where it would cover them; the view
      is rendered.
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
    up = _upright(_vec(bvp, "ViewUp"))
    eig = _vec(bvp, "EigenvalueSpectrum")
    center = _vec(bvp, "DataCenter")
    visible = _vec(bvp, "VisibleBounds")
    silhouette = _visible_points(bvp)
    valid = bool(bvp.GetPropertyValue("ViewValid"))
    device = bvp.GetPropertyValue("DeviceUsed")
    direction = best if which == "best" else worst
    result = ViewpointResult(
        direction=direction, which=which, best=best, worst=worst, view_up=up,
        eigenvalues=eig, center=center, visible_bounds=visible, valid=valid, device=device,
        filter=bvp, entropies=None, sign=1, camera_position=None)
    if not valid or sum(d * d for d in direction) < 0.5:
        _warn("no %s view direction for this volume (flat or constant opacity?): "
              "the camera was not changed" % which)
        result["valid"] = False
        return result

    sign = 1
    final = direction
    if disambiguate:
        # Each side is rendered once, by the screenshot its entropy is taken from; "+" last,
        # so that when it is kept (ties included) the camera is already there.
        entropies = {}
        for s, key in ((-1, "-"), (1, "+")):
            _fit_camera(view, silhouette, [s * d for d in direction], up, render=False)
            entropies[key] = _render_entropy(view)
        result["entropies"] = entropies
        sign = 1 if entropies["+"] >= entropies["-"] else -1
        final = [sign * d for d in direction]
    if disambiguate and sign == 1:
        simple.Render(view)  # the screenshot rendered offscreen: show it in the view
    else:
        _fit_camera(view, silhouette, final, up)
    result["direction"] = final
    result["center"] = [float(p) for p in view.CameraFocalPoint]
    result["visible_bounds"] = visible
    result["sign"] = sign
    result["camera_position"] = [float(p) for p in view.CameraPosition]
    return result


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _normalized(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v] if n > 0 else list(v)


def _perpendicular(v, hint=None):
    """A unit vector perpendicular to unit `v`: `hint` with its component along v removed,
    or any perpendicular when there is no usable hint."""
    if hint is not None:
        p = [h - _dot(hint, v) * x for h, x in zip(hint, v)]
        if _dot(p, p) > 1e-12:
            return _normalized(p)
    return _normalized([v[1], -v[0], 0.0] if abs(v[2]) < 0.9 else [0.0, v[2], -v[1]])


def _rotate(v, axis, angle):
    """`v` rotated by `angle` about unit `axis` (Rodrigues); angle 0 returns v exactly."""
    c, s = math.cos(angle), math.sin(angle)
    k_dot_v = _dot(axis, v)
    k_x_v = _cross(axis, v)
    return [x * c + kx * s + k * k_dot_v * (1.0 - c) for x, kx, k in zip(v, k_x_v, axis)]


def _turn_axis(a, b, hint=None):
    """(axis, angle) of the shortest rotation taking unit `a` to unit `b`. Opposite vectors
    have no shortest turn: it is about `hint` made perpendicular to a (the camera's view-up,
    so the camera swings round without rolling), or about any perpendicular."""
    angle = math.acos(max(-1.0, min(1.0, _dot(a, b))))
    axis = _cross(a, b)
    if _dot(axis, axis) > 1e-24 and math.pi - angle > 1e-6:
        return _normalized(axis), angle
    return _perpendicular(a, hint), angle


def _slerp(a, b, t, hint=None):
    """Unit vector a fraction t of the way from unit vector a to b along the great circle
    (t = 0: a, t = 1: b, exactly)."""
    if t >= 1.0:
        return list(b)
    axis, angle = _turn_axis(a, b, hint)
    return _rotate(a, axis, t * angle)


def _continuous_sign(current, direction):
    """+1 or -1: the sign of the best-view `direction` (v and -v are equally good) that is
    nearer the camera's `current` direction, so following never turns the camera by more
    than 90 degrees for a sign the PCA chose at random."""
    return -1 if _dot(current, direction) < 0.0 else 1


def _signed_angle(a, b, axis):
    """Angle turning a to b about `axis` (a, b perpendicular to it), in (-pi, pi]."""
    return math.atan2(_dot(axis, _cross(a, b)), _dot(a, b))


_MAX_STEPS_PER_SECOND = 60.0


def _animation_fractions(duration, min_steps, clock=None, sleep=None):
    """The fractions t in (0, 1] of a camera turn, one per rendered step, the last exactly
    1. Time-based: t is the elapsed share of `duration` seconds (as many steps as fit, at
    most 60 a second: a faster render waits for its time), but a step never advances more
    than 1 / min_steps, so a slow render still shows at least `min_steps` steps (and then
    takes longer). min_steps <= 1: one step; duration <= 0: min_steps equal steps."""
    clock = clock or time.monotonic
    sleep = sleep or time.sleep
    min_steps = int(min_steps)
    if min_steps <= 1:
        yield 1.0
        return
    if not duration > 0:
        for i in range(1, min_steps + 1):
            yield 1.0 if i == min_steps else float(i) / min_steps
        return
    start = clock()
    most, least = 1.0 / min_steps, 1.0 / (_MAX_STEPS_PER_SECOND * duration)
    t = 0.0
    while t < 1.0:
        on_time = (clock() - start) / duration
        t = min(1.0, t + most, max(on_time, t + least))
        if t > 1.0 - 1e-9:  # the sum of equal shares may fall short of 1 by rounding
            t = 1.0
        ahead = t * duration - (clock() - start)
        if ahead > 0:
            sleep(ahead)
        yield t


def _camera_state(view):
    position = [float(p) for p in view.CameraPosition]
    focal = [float(p) for p in view.CameraFocalPoint]
    offset = [f - p for f, p in zip(focal, position)]
    distance = math.sqrt(_dot(offset, offset))
    direction = _normalized(offset) if distance > 1e-9 else [0.0, 0.0, -1.0]
    up = _perpendicular(direction, [float(u) for u in view.CameraViewUp])
    return focal, direction, (distance if distance > 1e-9 else 1.0), up


def _place_camera(view, focal, direction, distance, up):
    view.CameraFocalPoint = list(focal)
    view.CameraPosition = [f - distance * d for f, d in zip(focal, direction)]
    view.CameraViewUp = list(up)


def turn_camera(view, center, direction, view_up=None, frames=4, duration=0.5, on_step=None,
                fit=None):
    """Turns the camera of `view` smoothly to look along `direction` at `center`: about
    `duration` seconds of rendered steps (as many as fit), the last one exactly along
    `direction`. A slow renderer still shows at least `frames` steps of a turn of 90
    degrees or more, and proportionally fewer of a smaller one: a step is at most
    90 / frames degrees (a turn under that is one step); duration 0: exactly `frames`
    equal steps; frames <= 1: at once.

    The direction turns on the great circle (slerp about the focal point, the distance
    kept; the focal point slides to `center`). The view-up turns with it (carried along
    the same rotation, so the picture does not roll); with `view_up` given, the roll
    needed to end on it is spread over the steps. ``on_step(i)`` (optional) is called after
    each rendered step (a batch script saves the frames there; with duration=0 the turn has
    exactly `frames` steps). ``fit`` (optional): a BestViewpoint filter (what
    best_viewpoint_filter returns); the turn then ends framed on the voxels it shows, as
    apply_best_viewpoint frames them (`center` is not used): the focal point slides to
    their middle and the distance (or parallel scale) changes over the steps. Returns the
    number of rendered steps."""
    simple = _simple()
    focal0, start, distance0, up0 = _camera_state(view)
    goal = _normalized([float(d) for d in direction])
    axis, angle = _turn_axis(start, goal, up0)
    carried_up = _perpendicular(goal, _rotate(up0, axis, angle))
    roll = 0.0
    if view_up is not None:
        roll = _signed_angle(carried_up, _perpendicular(goal, view_up), goal)
    distance, scale0, scale = distance0, float(view.CameraParallelScale), None
    if fit is not None:  # framed as the turn will end: its direction and view-up
        center, _, fitted, _, scale = _fitted_camera(
            view, _visible_points(fit), goal, view_up if view_up is not None else carried_up)
        distance = fitted if fitted > 0 else distance0
    center = [float(c) for c in center]
    # How far the picture moves: the turn, the roll, the focal point's slide (as seen from
    # the camera). A small move needs few steps for the eye to follow it, and each step is
    # a render: on a software renderer a widget edit while following would otherwise wait
    # for `frames` renders however little the view changes.
    slide = math.sqrt(sum((b - a) ** 2 for a, b in zip(focal0, center)))
    zoom = abs(math.log(distance / distance0))
    if scale is not None and scale > 0 < scale0:
        zoom = max(zoom, abs(math.log(scale / scale0)))
    move = max(abs(angle), abs(roll), math.atan2(slide, distance0), zoom)
    # (A batch script that saves every step as a movie frame, duration 0, gets `frames`.)
    least_steps = int(frames) if not duration > 0 else min(
        int(frames), max(1, int(math.ceil(move / (math.pi / 2) * frames - 1e-9))))
    steps = 0
    for t in _animation_fractions(duration, least_steps):
        d = _slerp(start, goal, t, up0)
        up = _rotate(_perpendicular(d, _rotate(up0, axis, t * angle)), d, t * roll)
        focal = [a + t * (b - a) for a, b in zip(focal0, center)]
        if scale is not None:
            view.CameraParallelScale = scale0 * (scale / scale0) ** t if scale0 > 0 < scale else scale
        # a zoom at a constant rate: the distance changes geometrically
        _place_camera(view, focal, d, distance0 * (distance / distance0) ** t,
                      _perpendicular(d, up))
        simple.Render(view)
        if on_step is not None:
            on_step(steps)
        steps += 1
    return steps


def follow_best_viewpoint(display, view=None, frames=4, which="best", duration=0.5,
                          **filter_properties):
    """Keeps the camera of `view` on the best view of what a "Gaussian TF Volume"
    `display` shows: now, and after every change of its GaussianWidgets the best
    viewpoint is recomputed from the widgets' opacity and the camera turns there
    (turn_camera: about `duration` seconds, at least `frames` rendered steps for a turn of
    90 degrees, fewer for a smaller one, the view-up carried along, the distance kept, the
    focal point sliding to the middle of the voxels the widgets show: the filter's
    VisibleBounds). Of the two equally good directions v
    and -v the one nearer the current camera is taken, so the camera never flips to the
    other side.
    Returns an object with .stop() (also stop_following()) and .state["result"]: the
    last update's ViewpointResult (direction, best, sign, steps, ...)."""
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
        best = _vec(bvp, "BestViewDirection" if which == "best" else "WorstViewDirection")
        if not bvp.GetPropertyValue("ViewValid") or _dot(best, best) < 0.5:
            _warn("follow_best_viewpoint: no %s view for these widgets; the camera stays"
                  % which)
            return
        sign = _continuous_sign(_camera_state(view)[1], best)
        direction = [sign * d for d in best]
        # Turned about the middle of what the widgets show (the input's middle when no
        # voxel is visible: VisibleBounds are then the input's bounds).
        visible = _vec(bvp, "VisibleBounds")
        center = [(visible[2 * a] + visible[2 * a + 1]) / 2.0 for a in range(3)]
        steps = turn_camera(view, center, direction, None, frames, duration)
        state["result"] = ViewpointResult(direction=direction, best=best, sign=sign,
                                          steps=steps, filter=bvp, which=which,
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
