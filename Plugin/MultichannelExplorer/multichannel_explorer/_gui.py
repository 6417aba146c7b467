"""What the GUI's Probe toggle and Brush Selection button run (pqMultichannelProbe.cxx):
the helpers on the active view / source, and the text the label over the view shows,
left in ``text`` for the C++ side to read. Errors become that text too (and a warning in
Output Messages), so a click never fails silently.

The helpers are called through the package (``multichannel_explorer.probe_at_pixel``),
so GUI tests can wrap them there.
"""

from ._common import _same_proxy, _simple, _warn

text = ""


def _numbers(values, limit=6):
    shown = ", ".join("%.4g" % v for v in list(values)[:limit])
    return shown + (", ..." if len(values) > limit else "")


def describe(hit):
    """The label's text for a probe() result."""
    lines = ["Voxel (%d, %d, %d)   id %d" % (tuple(hit.index) + (hit.point_id,)),
             "position     (%s)" % _numbers(hit.position),
             "coordinates  (%s)" % _numbers(hit.coordinates)]
    if hit.foreground is not None:
        lines.append("foreground   %d" % hit.foreground)
    for name, value in sorted(hit.channels.items()):
        shown = _numbers(value) if isinstance(value, list) else "%.6g" % value
        lines.append("%-12s %s" % (name[:12], shown))
    if hit.features is not None:
        lines.append("features     %s" % _numbers(hit.features))
    return "\n".join(lines)


def probe(x, y):
    """Probe of display pixel (x, y) of the active view."""
    global text
    import multichannel_explorer as mce

    simple = _simple()
    view = simple.GetActiveView()
    try:
        if mce.picking._gaussian_tf_in(view) is None and mce.picking._domain_in(view):
            hit = mce.probe_domain_at_pixel(view, x, y)  # a click in the domain view
        else:
            hit = mce.probe_at_pixel(view, x, y)
        text = describe(hit) if hit is not None else "Probe: nothing visible at this pixel"
    except ValueError as error:  # nothing to probe in this view: the label says so
        text = "Probe: %s" % error
    except Exception as error:  # noqa: BLE001 - shown to the user, not swallowed
        text = "Probe: %s" % error
        _warn(text)
    return text


def _selected_domain():
    """The ReducedDomain whose points are selected: the active source if it is one, else
    any with a selection (a rubber band also selects the widget spheres and markers, and
    one of those may have become the active source)."""
    simple = _simple()
    active = simple.GetActiveSource()
    domains = [p for p in simple.GetSources().values()
               if p.SMProxy.GetXMLName() == "ReducedDomain"]
    selected = [p for p in domains if p.SMProxy.GetSelectionInput(0) is not None]
    for proxy in selected:
        if _same_proxy(proxy, active):
            return proxy
    return selected[0] if selected else active


def brush():
    """brush() of the points selected in the reduced domain."""
    global text
    import multichannel_explorer as mce

    try:
        count = mce.brush(_selected_domain())
        text = "Brushed %d voxel%s" % (count, "" if count == 1 else "s")
    except ValueError as error:  # nothing selected: the label says so
        text = "Brush: %s" % error
    except Exception as error:  # noqa: BLE001 - shown to the user, not swallowed
        text = "Brush: %s" % error
        _warn(text)
    return text
