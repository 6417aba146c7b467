"""The multichannel transfer function's display: showing a volume of reduced coordinates as
a "Gaussian TF Volume" with Gaussian widgets, and finding the Volume / Gaussian TF
display of a source in a view (its widgets, its coordinate array).
"""

import math

from ._common import _TracedProperties, _check_parallel_rendering, _is_representation, _simple

__all__ = [
    "GAUSSIAN_TF_REPRESENTATION",
    "check_widget_values",
    "edit_widget",
    "show_gaussian_tf",
    "show_widgets",
]


GAUSSIAN_TF_REPRESENTATION = "Gaussian TF Volume"


def _volume_display(source, view):
    """The source's representation in `view` when it is visible as a Volume, else None."""
    if view is None:
        return None
    from paraview import servermanager

    rep = servermanager.GetRepresentation(source, view)
    if rep is None:
        return None
    try:
        if not rep.Visibility or rep.Representation != "Volume":
            return None
    except AttributeError:
        return None
    return rep


def _gaussian_tf_display(source, view):
    """The source's representation in `view` when it is visible as a Gaussian TF Volume."""
    if view is None or source is None:
        return None
    from paraview import servermanager

    rep = servermanager.GetRepresentation(source, view)
    try:
        if rep is None or not rep.Visibility or \
                rep.Representation != GAUSSIAN_TF_REPRESENTATION:
            return None
    except AttributeError:
        return None
    return rep


def _gaussian_display(display, what):
    """`display` when it is a Gaussian TF Volume representation, else ValueError."""
    # Every image-data display carries the GaussianWidgets property: the representation
    # type says whether the widgets are what it draws.
    shown = None
    if display is not None and _is_representation(display) and \
            display.GetProperty("GaussianWidgets") is not None:
        shown = display.SMProxy.GetProperty("Representation").GetElement(0)
        if shown == GAUSSIAN_TF_REPRESENTATION:
            return display
    raise ValueError("%s needs a \"%s\" display (a representation proxy), not %s"
                     % (what, GAUSSIAN_TF_REPRESENTATION,
                        "a display shown as %s" % shown if shown else repr(display)))


def _widget_values(display):
    return [float(v) for v in display.GetProperty("GaussianWidgets")]


def _coordinates_name(display):
    """Name of the coordinate array a Gaussian TF display maps through its widgets."""
    prop = display.SMProxy.GetProperty("CoordinateArray")
    if prop is not None and prop.GetNumberOfElements() > 0:
        # An array selection (association, name) or a plain name: the name is last.
        name = prop.GetElement(prop.GetNumberOfElements() - 1)
        if name:
            return str(name)
    return "ReducedCoordinates"


def _source_and_display(target, view=None):
    """(source, Gaussian TF display or None) for a source or a representation proxy."""
    if target is None:
        raise ValueError("no source or display given")
    if _is_representation(target):
        return target.Input, target
    if view is None:
        view = _simple().GetActiveView()
    return target, _gaussian_tf_display(target, view)


def _flat_widgets(widgets):
    """A flat list of floats from a flat list or from 8-value widgets."""
    flat = []
    for item in widgets or ():
        if isinstance(item, (list, tuple)):
            flat.extend(float(v) for v in item)
        else:
            flat.append(float(item))
    return flat


WIDGET_FIELDS = ("cx", "cy", "cz", "sigma", "r", "g", "b", "opacity")
# A centre this far out, or a sigma this many times the reduced domain's size, is no
# widget anyone placed: a unit or parsing error upstream.
ABSURD_CENTRE = 1e30
ABSURD_SIGMA_FACTOR = 1e6


def check_widget_values(values, where="GaussianWidgets", domain_size=None, first=0):
    """Raises ValueError naming the widget and the field when a value of the flat widget
    list (8 per widget: cx, cy, cz, sigma, r, g, b, opacity) is not finite (nan, inf), a
    centre lies beyond 1e30, or sigma exceeds `domain_size` (the reduced domain's largest
    extent, when known; else 1e30) x 1e6; also when the list is not a multiple of 8. A
    ParaView property takes such values as they are (and a state file's "nan" loads as 0),
    so the helpers that set GaussianWidgets check them first. Widgets are numbered from
    `first` (the index of values[0:8] in the display's list). Returns `values`."""
    import math

    if len(values) % len(WIDGET_FIELDS):
        raise ValueError("%s: %d values, not a multiple of 8 (cx, cy, cz, sigma, r, g, b, "
                         "opacity per widget)" % (where, len(values)))
    sigma_limit = ABSURD_SIGMA_FACTOR * domain_size if domain_size else ABSURD_CENTRE
    for i, value in enumerate(values):
        widget, field = divmod(i, len(WIDGET_FIELDS))
        widget += first
        name = WIDGET_FIELDS[field]
        if not math.isfinite(value):
            raise ValueError("%s: widget %d's %s is %r, not a finite number"
                             % (where, widget, name, value))
        if name in ("cx", "cy", "cz") and abs(value) > ABSURD_CENTRE:
            raise ValueError("%s: widget %d's centre %s = %g lies beyond %g"
                             % (where, widget, name, value, ABSURD_CENTRE))
        if name == "sigma" and value > sigma_limit:
            raise ValueError("%s: widget %d's sigma = %g exceeds %g (%s)"
                             % (where, widget, value, sigma_limit,
                                "1e6 x the reduced domain's size %g" % domain_size
                                if domain_size else "no widget is that wide"))
    return values


def _domain_size(source, coordinates):
    """The largest extent of the coordinate array over the volume, or None when unknown."""
    try:
        from ._voxels import _coordinate_range

        size = max(hi - lo for lo, hi in _coordinate_range(source, coordinates))
    except Exception:  # no such array yet, or no range: the absolute limits apply
        return None
    # An array whose range is not known yet reports VTK's empty range (1e299, -1e299).
    return size if math.isfinite(size) and 0 < size < 1e30 else None


def show_gaussian_tf(source, view=None, widgets=(), coordinates="ReducedCoordinates",
                     blend="Composite", classification="Per sample"):
    """Shows `source` (image data with a 2- or 3-component point array of reduced
    coordinates, e.g. the output of DimensionReduction) as a "Gaussian TF Volume" in
    `view` (default: the active render view) and returns the display.

    ``widgets``: a flat list of 8 numbers per widget (cx, cy, cz, sigma, r, g, b,
    opacity) or a sequence of such 8-tuples; ``coordinates``: the point array of reduced
    coordinates; ``blend``: "Composite" or "Maximum Intensity"; ``classification``:
    "Per sample" (the widgets evaluated at every ray sample in the GPU ray caster's
    shader, at most 64 widgets) or "Per voxel" (an RGBA array per voxel, CPU or CUDA).
    Edit the widgets later with ``display.GaussianWidgets = [...]`` (or one of them with
    edit_widget) and ``Render()``: per sample only shader uniforms change, per voxel only
    the colours are recomputed; the volume is not delivered again::

        display = mce.show_gaussian_tf(reduction, view,
                                       widgets=[(0.2, 0.1, 0, 0.05, 1, 0, 0, 1),
                                                (0.7, 0.4, 0, 0.05, 0, 1, 0, 1)],
                                       blend="Maximum Intensity")
    """
    simple = _simple()
    if view is None:
        view = simple.GetActiveViewOrCreate("RenderView")
    _check_parallel_rendering(view)
    # The first thing shown in a view: frame it, as the GUI does (else the camera may sit
    # inside the volume, and a turn to the best view keeps that distance).
    empty = not any(getattr(r, "Visibility", 0) for r in view.Representations)
    display = simple.Show(source, view)
    if GAUSSIAN_TF_REPRESENTATION not in display.GetProperty("Representation").Available:
        raise RuntimeError('"%s" is not a representation of this source (image data '
                           "only; is the MultichannelExplorer plugin loaded?)"
                           % GAUSSIAN_TF_REPRESENTATION)
    display.SetRepresentationType(GAUSSIAN_TF_REPRESENTATION)
    values = check_widget_values(
        _flat_widgets(widgets), "show_gaussian_tf widgets",
        _domain_size(source, str(coordinates)) if widgets else None)
    with _TracedProperties(display):  # recorded in a trace being recorded
        display.CoordinateArray = str(coordinates)
        display.GaussianBlendMode = str(blend)
        display.Classification = str(classification)
        display.GaussianWidgets = values
    if empty:
        simple.ResetCamera(view)
    return display


def _widget_index(names, count, which):
    """The index of widget `which` (a name of GaussianWidgetNames or an index, negative
    from the end) among `count` widgets; ValueError naming the choices when there is none."""
    if isinstance(which, str):
        matches = [i for i, n in enumerate(names[:count]) if n == which]
        if len(matches) == 1:
            return matches[0]
        if matches:
            raise ValueError("%d widgets are named %r (widgets %s): give the index"
                             % (len(matches), which, ", ".join(map(str, matches))))
        raise ValueError("no widget is named %r; the widgets are %s" % (
            which, ", ".join("%d %r" % (i, n) for i, n in enumerate(names[:count])) or
            "none"))
    index = int(which)
    if not -count <= index < count:
        raise ValueError("widget %d does not exist: the display has %d widget%s"
                         % (index, count, "" if count == 1 else "s"))
    return index % count


def edit_widget(target, which, center=None, sigma=None, color=None, opacity=None,
                shown=None, name=None, view=None):
    """Changes one Gaussian widget of `target` (a "Gaussian TF Volume" display, or the
    volume shown as one in `view`) and returns it (8 numbers, as in GaussianWidgets).
    `which` is the widget's name (GaussianWidgetNames, e.g. the names auto_widgets gives)
    or its index (0 is the first, -1 the last). Only what is given changes: `center` (2 or
    3 reduced coordinates), `sigma`, `color` (r, g, b in [0, 1]), `opacity` (the peak
    opacity, in [0, 1]), `name`. A hidden widget (the editor's check box, or the cluster of
    most voxels that auto_widgets seeds hidden) draws nothing: `opacity` sets the opacity
    it gets back when shown; `shown=True` shows it, `shown=False` hides a shown one (as the
    editor does: opacity 0 in GaussianWidgets, its opacity kept in GaussianWidgetsHidden).
    The widgets change in one property update, so follow_best_viewpoint and the reduced
    domain see the edit once::

        mce.edit_widget(display, 0, color=(0.9, 0.1, 0.1), opacity=0.3)
        mce.edit_widget(display, 0, shown=False)    # hidden: the camera may turn
        mce.edit_widget(display, 0, shown=True)     # back, at opacity 0.3
    """
    display = _gaussian_display(_source_and_display(target, view)[1], "edit_widget")
    values, hidden, names = _widget_state(display)
    count = len(hidden)
    index = _widget_index(names, count, which)
    widget = values[8 * index:8 * index + 8]
    if center is not None:
        center = [float(c) for c in center]
        if len(center) not in (2, 3):
            raise ValueError("a widget's centre is 2 or 3 numbers, not %r" % (center,))
        widget[0:3] = (center + [0.0])[:3]
    if sigma is not None:
        if not float(sigma) > 0:
            raise ValueError("a widget's sigma is positive, not %r" % (sigma,))
        widget[3] = float(sigma)
    if color is not None:
        color = [float(c) for c in color]
        if len(color) != 3 or not all(0 <= c <= 1 for c in color):
            raise ValueError("a widget's colour is 3 numbers in [0, 1], not %r" % (color,))
        widget[4:7] = color
    if opacity is not None and not 0 <= float(opacity) <= 1:
        raise ValueError("a widget's opacity is in [0, 1], not %r" % (opacity,))
    is_hidden = hidden[index] >= 0
    peak = float(opacity) if opacity is not None else \
        (hidden[index] if is_hidden else widget[7])
    if shown is None:
        shown = not is_hidden
    widget[7] = peak if shown else 0.0
    hidden[index] = -1.0 if shown else peak
    values[8 * index:8 * index + 8] = widget
    check_widget_values(widget, "edit_widget", None, first=index)
    if name is not None:
        names = (names + [""] * count)[:count]
        names[index] = str(name)
    _set_widget_state(display, values, hidden, names if name is not None else None)
    return widget


def show_widgets(target, which, view=None):
    """Shows the widgets `which` (names of GaussianWidgetNames or indices, as edit_widget
    takes them) of `target` (a "Gaussian TF Volume" display, or the volume shown as one in
    `view`) and hides every other one, as the editor's check boxes would, in one property
    update (follow_best_viewpoint turns the camera once). A widget shown again gets back
    the opacity it had; a hidden one keeps its own. Returns the indices shown::

        mce.show_widgets(display, [0])            # the first widget alone
        mce.show_widgets(display, range(len(display.GaussianWidgets) // 8))  # all again
    """
    display = _gaussian_display(_source_and_display(target, view)[1], "show_widgets")
    values, hidden, names = _widget_state(display)
    count = len(hidden)
    if isinstance(which, (str, int)):
        which = [which]
    chosen = sorted(set(_widget_index(names, count, w) for w in which))
    for index in range(count):
        peak = hidden[index] if hidden[index] >= 0 else values[8 * index + 7]
        shown = index in chosen
        values[8 * index + 7] = peak if shown else 0.0
        hidden[index] = -1.0 if shown else peak
    _set_widget_state(display, values, hidden)
    return chosen


def _widget_state(display):
    """(GaussianWidgets, GaussianWidgetsHidden, GaussianWidgetNames) of `display` as lists;
    the hidden list with one entry per widget (-1: shown), as the editor reads it."""
    values = _widget_values(display)
    count = len(values) // len(WIDGET_FIELDS)
    hidden = [float(v) for v in display.GetProperty("GaussianWidgetsHidden")]
    if len(hidden) != count:  # the editor ignores a list that does not match: all shown
        hidden = [-1.0] * count
    return values, hidden, [str(v) for v in display.GetProperty("GaussianWidgetNames")]


def _set_widget_state(display, values, hidden, names=None):
    """Sets the widgets, which are hidden and (unless None) their names in one call:
    observers (show_dual_domain, follow_best_viewpoint) see the whole edit once. The
    widgets go in through SetElements: element-wise assignment (display.GaussianWidgets =
    ...) first grows the list with zeros, and observers would see a widget of sigma 0."""
    with _TracedProperties(display):  # recorded in a trace being recorded
        display.GaussianWidgetsHidden = hidden if any(h >= 0 for h in hidden) else []
        if names is not None:
            display.GaussianWidgetNames = names
        display.SMProxy.GetProperty("GaussianWidgets").SetElements(values, len(values))
        display.SMProxy.UpdateVTKObjects()
