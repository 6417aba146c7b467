"""State files (.pvsm) with Gaussian widgets: checked before ParaView loads them.

ParaView's state loader reads each property element with C++ stream parsing, so a "nan" or
"inf" written into a state file (by hand, by a script, by another tool) loads as 0.0: a
widget silently moves to the origin or vanishes. check_state_file reads the file's
GaussianWidgets elements as text and applies check_widget_values to them, naming the
proxy, the widget and the field; load_state checks, then loads.
"""

from .transfer_function import check_widget_values

__all__ = [
    "check_state_file",
    "load_state",
]


def check_state_file(path):
    """Raises ValueError when a GaussianWidgets property of the state file `path` holds a
    value that is not a finite number (nan, inf, or text that is no number at all), a
    centre beyond 1e30 or an absurd sigma (check_widget_values, without the domain's size,
    which the file does not hold). Returns the number of widget lists checked."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as exc:
        raise ValueError("%s: not a readable state file (%s)" % (path, exc))
    checked = 0
    for proxy in root.iter("Proxy"):
        for prop in proxy.findall("Property"):
            if prop.get("name") != "GaussianWidgets":
                continue
            elements = sorted(prop.findall("Element"), key=lambda e: int(e.get("index", 0)))
            values = []
            where = "%s: GaussianWidgets of %s proxy %s" % (path, proxy.get("type"),
                                                            proxy.get("id"))
            for e in elements:
                text = e.get("value", "")
                try:
                    values.append(float(text))
                except ValueError:
                    index = int(e.get("index", len(values)))
                    raise ValueError("%s: widget %d's %s is %r, not a number"
                                     % (where, index // 8,
                                        ("cx", "cy", "cz", "sigma", "r", "g", "b",
                                         "opacity")[index % 8], text))
            check_widget_values(values, where)
            checked += 1
    return checked


def load_state(path, **kwargs):
    """paraview.simple.LoadState(path, **kwargs) after check_state_file(path)."""
    from paraview import simple

    check_state_file(path)
    return simple.LoadState(path, **kwargs)
