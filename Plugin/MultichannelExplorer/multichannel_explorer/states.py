"""State files with the plugin's proxies: checked before ParaView loads them, and Python
state files that load the plugin.

ParaView's state loader reads each property element with C++ stream parsing, so a "nan" or
"inf" written into a state file (by hand, by a script, by another tool) loads as 0.0: a
widget silently moves to the origin or vanishes. check_state_file reads the file's
GaussianWidgets elements as text and applies check_widget_values to them, naming the
proxy, the widget and the field; load_state checks, then loads.

ParaView 5.11 records no plugins in its state files: a .pvsm holds proxies only, and a
Python state (File > Save State as .py, paraview.smstate.get_state) starts with
`from paraview.simple import *` and creates the plugin's readers, filters and
representation by name, which fails in a session without the plugin. Once this package is
imported, every Python state ParaView writes in that session (smstate.get_state, which
the GUI's Save State and simple-level scripts use) gets the plugin's LoadPlugin lines
right after that import, server side first in a client-server session, as traces do
(_common._trace_plugin_load); save_state writes either kind of file, a Python one with
those lines. A .pvsm cannot carry them: load the plugin before loading one (Tools >
Manage Plugins, with Auto Load, or PV_PLUGIN_PATH).
"""

from .transfer_function import check_widget_values

__all__ = [
    "check_state_file",
    "load_state",
    "save_state",
    "state_plugin_lines",
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


def state_plugin_lines():
    """The lines that load this plugin where it is loaded now (server side first in a
    client-server session), as a state or trace needs them: [] when it is not loaded."""
    from ._common import _plugin_files

    lines = []
    for filename, remote in sorted(_plugin_files(), key=lambda f: not f[1]):
        lines.append("LoadPlugin(%r, remote=%s, ns=globals())" % (filename, remote))
    if lines:
        lines.insert(0, "# load the MultichannelExplorer plugin (its readers, filters and "
                        "representation)")
    return lines


def _with_plugin_lines(state):
    """A Python state (text or, raw, a list of lines) with state_plugin_lines() right after
    its `from paraview.simple import *` (at the top when it has none)."""
    lines = state_plugin_lines()
    if not lines:
        return state
    raw = isinstance(state, list)
    data = list(state) if raw else state.split("\n")
    anchor = "from paraview.simple import *"
    at = next((i + 1 for i, line in enumerate(data) if line.strip() == anchor), 0)
    if at == 0:
        lines = [anchor] + lines
    data[at:at] = lines
    return data if raw else "\n".join(data)


def _install_state_hook():
    """Makes paraview.smstate.get_state (the Python state of File > Save State and of
    scripts) load this plugin: its output gets state_plugin_lines(). Once per process."""
    try:
        from paraview import smstate
    except ImportError:  # pragma: no cover - ParaView without Python state support
        return
    original = smstate.get_state
    if getattr(original, "_mcv_loads_plugin", False):
        return

    def get_state(*args, **kwargs):
        return _with_plugin_lines(original(*args, **kwargs))

    get_state.__doc__ = original.__doc__
    get_state._mcv_loads_plugin = True
    smstate.get_state = get_state


def save_state(path):
    """Saves the session's state to `path`: a Python state for a .py file (ParaView's
    Python state, which loads this plugin before it creates anything of it), else a .pvsm
    (paraview.simple.SaveState; ParaView records no plugin in one: load the plugin before
    loading it). Raises ValueError for another extension or a folder that does not exist."""
    import os

    from paraview import simple, smstate

    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise ValueError("%s: the folder %s does not exist" % (path, folder))
    extension = os.path.splitext(path)[1].lower()
    if extension == ".py":
        _install_state_hook()
        with open(path, "w") as f:
            f.write(smstate.get_state())
            f.write("\n")
    elif extension == ".pvsm":
        simple.SaveState(path)
    else:
        raise ValueError("%s: a state file is .pvsm or .py (got %r)" % (path, extension))
    return path
