"""What the GUI's Probe toggle, Add Widget Here and Brush Selection buttons run (pqMultichannelProbe.cxx),
and the Gaussian widgets editor's Save... and Load... (on_display):
the helpers on the active view / source, and the text the label over the view shows,
left in ``text`` for the C++ side to read. Errors become that text too (and a warning in
Output Messages), so a click never fails silently.

The helpers are called through the package (``multichannel_explorer.probe_at_pixel``),
so GUI tests can wrap them there.
"""

from ._common import _gui_text, _same_proxy, _simple, _warn

text = ""
last_hit = None  # the last probe's result: "Add Widget Here" puts a widget there


def _numbers(values, limit=6):
    shown = ", ".join("%.4g" % v for v in list(values)[:limit])
    return shown + (", ..." if len(values) > limit else "")


def describe(hit):
    """The label's text for a probe() result: one line per value, the names in a column
    as wide as the longest (channel names are whole), an atlas value with its label."""
    channels = sorted(hit.channels.items())
    width = max([len("coordinates")] + [len(name) for name, _ in channels])
    row = "%%-%ds  %%s" % width
    lines = ["Voxel (%d, %d, %d)   id %d" % (tuple(hit.index) + (hit.point_id,)),
             row % ("position", "(%s)" % _numbers(hit.position)),
             row % ("coordinates", "(%s)" % _numbers(hit.coordinates))]
    if hit.foreground is not None:
        lines.append(row % ("foreground", "%d" % hit.foreground))
    labels = hit.get("labels") or {}
    for name, value in channels:
        shown = _numbers(value) if isinstance(value, list) else "%.6g" % value
        if name in labels:
            shown += "  " + labels[name]
        lines.append(row % (name, shown))
    if hit.features is not None:
        lines.append(row % ("features", _numbers(hit.features)))
    return "\n".join(lines)


def probe(x, y):
    """Probe of display pixel (x, y) of the active view."""
    global text, last_hit
    import multichannel_explorer as mce

    def run():
        global last_hit
        view = _simple().GetActiveView()
        if mce.picking._gaussian_tf_in(view) is None and mce.picking._domain_in(view):
            hit = mce.probe_domain_at_pixel(view, x, y, render=False)  # the domain view
        else:
            # The views are rendered by the GUI after the answer is shown.
            hit = mce.probe_at_pixel(view, x, y, render=False)
        last_hit = hit if hit is not None else last_hit
        return describe(hit) if hit is not None else "Probe: nothing visible at this pixel"

    text = _gui_text("Probe", run)  # nothing to probe in this view: the label says so
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

    def run():
        count = mce.brush(_selected_domain())
        return "Brushed %d voxel%s" % (count, "" if count == 1 else "s")

    text = _gui_text("Brush", run)  # nothing selected: the label says so
    return text


def add_widget():
    """add_widget_at() the last probed voxel's coordinates."""
    global text
    import multichannel_explorer as mce

    def run():
        if last_hit is None or last_hit.display is None:
            raise ValueError("probe a voxel of a \"Gaussian TF Volume\" first")
        widget = mce.add_widget_at(last_hit.display, last_hit)
        count = len(last_hit.display.GaussianWidgets) // 8
        _simple().Render()
        return "Widget %d added at (%s), sigma %.3g" % (count, _numbers(widget[:3]), widget[3])

    text = _gui_text("Add Widget Here", run)
    return text


def on_display(name, call):
    """call(display) on the representation registered as `name` (the Gaussian widgets
    editor's display): ``text`` is "" when it worked, else the error, which the editor
    shows in a message box (a bad transfer-function file, a missing model)."""
    global text
    from paraview import servermanager

    try:
        proxy = servermanager.ProxyManager().SMProxyManager.GetProxy("representations", name)
        if proxy is None:
            raise ValueError("no display named %s" % name)
        call(servermanager._getPyProxy(proxy))
        text = ""
    except ValueError as error:
        text = str(error)
    except Exception as error:  # noqa: BLE001 - shown to the user, not swallowed
        text = "%s: %s" % (type(error).__name__, error)
        _warn(text)
    return text
