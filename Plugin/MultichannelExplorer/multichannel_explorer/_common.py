"""Shared helpers of the multichannel_explorer package (private): paraview.simple on
demand, warnings, proxy look-ups and property observers.

Module-level state: ``_followers``, the one list of live observers (_Follower) of
follow_best_viewpoint and show_dual_domain; stop_following() empties it. Other modules
import the list itself and only append to it or pop from it, never rebind it.
"""


_FILTER_XML_NAME = "BestViewpoint"

# A coordinate array of this type (VTK_UNSIGNED_SHORT) holds IEEE binary16 bits:
# DimensionReduction's CoordinatePrecision Float16 (VTK 9.2 has no half-float array).
_FLOAT16_STORAGE = 5


def _is_float16(array):
    """Whether a coordinate array (a vtkDataArray or ParaView's array information) holds
    float16 values."""
    return array is not None and array.GetDataType() == _FLOAT16_STORAGE


def coordinate_values(array):
    """The values of a reduced-coordinate array (vtkDataArray: float32, or float16 stored
    as uint16 bits) as a float32 numpy array of shape (tuples, components); float16 is
    decoded through numpy's float16 view of the bits (exact: every half is a float)."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy

    values = vtk_to_numpy(array)
    if _is_float16(array):
        values = values.view(numpy.float16)
    return values.astype(numpy.float32).reshape(array.GetNumberOfTuples(),
                                                 array.GetNumberOfComponents())


def _coordinate_tuple(array, t):
    """Tuple t of a coordinate array as floats (float16 decoded), without numpy."""
    values = array.GetTuple(t)
    if not _is_float16(array):
        return tuple(float(v) for v in values)
    import struct

    bits = [int(v) for v in values]
    return struct.unpack("<%de" % len(bits), struct.pack("<%dH" % len(bits), *bits))


def _simple():
    from paraview import simple

    return simple


def _view_time(view=None):
    """The time the helpers update their filters at: `view`'s time (the time step it
    shows), else the active view's, else the animation's (the time keeper's). A proxy's
    UpdatePipeline() without a time re-runs at whatever time was last asked of it (the
    first time step for a new filter), not the one on screen."""
    simple = _simple()
    view = view if view is not None else simple.GetActiveView()
    if view is not None and hasattr(view, "ViewTime"):
        return float(view.ViewTime)
    return float(simple.GetTimeKeeper().Time)


def _display_view(display):
    """The view that holds `display` (a representation proxy), else None."""
    for view in _simple().GetViews():
        if any(_same_proxy(rep, display) for rep in view.Representations):
            return view
    return None


def _filter(name):
    """The paraview.simple constructor of the plugin's filter `name`. LoadPlugin(...,
    ns=globals()) adds the plugin's filters to the caller's namespace only; they are added
    to paraview.simple's own here, so every helper works however the plugin was loaded
    (pvpython, pvbatch, the GUI's Python shell)."""
    simple = _simple()
    _check_server_plugin()  # the plugin missing on the server: say that, not less
    ctor = getattr(simple, name, None)
    if ctor is None:
        simple._add_functions(vars(simple))
        ctor = getattr(simple, name, None)
    if ctor is None:
        raise RuntimeError(
            "The %s filter is not available: load the MultichannelExplorer plugin first, "
            "e.g. LoadPlugin(path, remote=False, ns=globals())" % name)
    _trace_plugin_load()
    return ctor


_PLUGIN_NAME = "MultichannelExplorer"
_traced_plugin_for = [None]  # the trace output that already loads the plugin


def _tracing():
    """Whether a ParaView trace is being recorded (Tools > Start Trace, smtrace)."""
    try:
        from paraview.modules.vtkRemotingServerManager import vtkSMTrace
    except ImportError:  # pragma: no cover - ParaView without the tracer
        return False
    return vtkSMTrace.GetActiveTracer() is not None


def _plugin_files():
    """[(file name, remote)] of this plugin as loaded on the client and, in a
    client-server session, on the server."""
    from paraview import servermanager

    manager = servermanager.vtkSMProxyManager.GetProxyManager().GetPluginManager()
    found = []
    infos = [(manager.GetLocalInformation(), False)]
    connection = servermanager.ActiveConnection
    if connection is not None and connection.IsRemote():
        infos.append((manager.GetRemoteInformation(connection.Session), True))
    for info, remote in infos:
        for i in range(info.GetNumberOfPlugins() if info is not None else 0):
            if info.GetPluginName(i) == _PLUGIN_NAME and info.GetPluginLoaded(i):
                found.append((info.GetPluginFileName(i), remote))
                break
    return found


def _check_server_alive():
    """In a client-server session, a RuntimeError when the connection to the server is
    lost (the server ended or was killed, e.g. during an update): what the helpers would
    read back otherwise is empty data, and their own messages would mislead."""
    from paraview import servermanager

    connection = servermanager.ActiveConnection
    if connection is None or not connection.IsRemote():
        return
    # ParaView 5.11 marks the session dead only once the client has processed the lost
    # socket (the GUI's event loop); a script sees an empty volume first: _Grid and
    # brush() name the lost connection as a likely cause then.
    if not connection.Session.GetIsAlive():
        raise RuntimeError(
            "The connection to the pvserver (%s) is lost: the server ended or was killed "
            "(see its output). Start it again, Connect() and load the plugin on both sides."
            % connection.GetURI())


def _remote_hint():
    """The words added to an 'empty volume' error in a client-server session."""
    from paraview import servermanager

    connection = servermanager.ActiveConnection
    if connection is None or not connection.IsRemote():
        return ""
    return (" (in a client-server session this is also what a lost connection to the "
            "pvserver %s looks like: the server ended or was killed; see its output)"
            % connection.GetURI())


def _check_parallel_rendering(view):
    """Raises RuntimeError under `mpiexec pvbatch --mpi` when a process of the run cannot
    render. ParaView asks every process for OpenGL (3.2) through its display when a view is
    made; if one has none, only process 0 renders, yet the first render of a volume still
    redistributes the data for ordered compositing, a step all processes must join: ParaView
    5.11 then waits forever (process 0 in an MPI all-gather, the others waiting for the next
    request). Nothing to check in a built-in or client-server session (no such step)."""
    from paraview import servermanager

    pm = servermanager.vtkProcessModule.GetProcessModule()
    if (pm.GetProcessType() != servermanager.vtkProcessModule.PROCESS_BATCH or
            pm.GetNumberOfLocalPartitions() < 2):
        return
    try:
        available = view.GetClientSideObject().GetRemoteRenderingAvailable()
    except AttributeError:  # not a render view
        return
    if not available:
        raise RuntimeError(
            "A process of this pvbatch --mpi run (%d processes) cannot render: ParaView found "
            "no OpenGL 3.2 through its display when the view was made (\"remote rendering "
            "not available\"). Its first volume render would wait forever, so nothing is "
            "shown. Give every process a display that renders (e.g. run mpiexec under one "
            "xvfb-run -a, and check that each process gets DISPLAY and XAUTHORITY), or run "
            "pvbatch without --mpi." % pm.GetNumberOfLocalPartitions())


def _check_server_plugin():
    """In a client-server session, a RuntimeError that names what is missing when the
    plugin is loaded on the client but not on the server (its filters would be created on
    the client only, and the server would fail or return nothing), or when the connection
    is lost (_check_server_alive)."""
    from paraview import servermanager

    connection = servermanager.ActiveConnection
    if connection is None or not connection.IsRemote():
        return
    _check_server_alive()
    manager = servermanager.vtkSMProxyManager.GetProxyManager().GetPluginManager()
    info = manager.GetRemoteInformation(connection.Session)
    for i in range(info.GetNumberOfPlugins() if info is not None else 0):
        if info.GetPluginName(i) == _PLUGIN_NAME and info.GetPluginLoaded(i):
            return
    local = [f for f, remote in _plugin_files() if not remote]
    raise RuntimeError(
        "The %s plugin is not loaded on the server (%s): its filters (DimensionReduction, "
        "ReducedDomain, ExtractVoxels, ...) cannot run there. Load it on the server too: "
        "LoadPlugin(%r, remote=True, ns=globals()) (a path on the server's machine), or "
        "Tools > Manage Plugins > Load Remote in the GUI."
        % (_PLUGIN_NAME, connection.GetURI() if hasattr(connection, "GetURI") else
           "the connected pvserver", local[0] if local else "MultichannelExplorer.so"))


def _trace_plugin_load():
    """In a trace being recorded, once: the LoadPlugin lines of this plugin (server side
    first) right after the trace's `from paraview.simple import *`, so that the trace
    loads the plugin before anything of it (a reader, a filter) is created."""
    if not _tracing():
        return
    from paraview import smtrace

    output = smtrace.Trace.Output
    if output is None or _traced_plugin_for[0] is output:
        return
    _traced_plugin_for[0] = output
    from .states import state_plugin_lines  # states imports this module

    lines = state_plugin_lines()
    if not lines:
        return
    lines.insert(0, "")
    data = output.raw_data()
    anchor = "from paraview.simple import *"
    at = next((i + 1 for i, line in enumerate(data) if line == anchor), 0)
    data[at:at] = lines


class _TracedProperties(object):
    """Properties that the block sets on `proxies` are recorded in a ParaView trace being
    recorded, as the GUI's property editors record theirs (smtrace.PropertiesModified,
    the item SM_SCOPED_TRACE(PropertiesModified) makes); nothing without a trace::

        from multichannel_explorer._common import _TracedProperties
        with _TracedProperties(display):
            display.GaussianWidgets = widgets
    """

    def __init__(self, *proxies):
        self.proxies = [p for p in proxies if p is not None]
        self.items = []

    def __enter__(self):
        if _tracing():
            from paraview import smtrace

            for proxy in self.proxies:
                try:
                    self.items.append(
                        smtrace._create_trace_item_internal("PropertiesModified", [proxy]))
                except smtrace.Untraceable:
                    pass
        return self

    def __exit__(self, *unused):
        items, self.items = self.items, []
        for item in reversed(items):
            item.finalize()
        return False


def _warn(message):
    """Warnings go where ParaView shows them (Output Messages in the GUI, stderr in
    pvpython/pvbatch)."""
    try:
        from vtkmodules.vtkCommonCore import vtkOutputWindow

        vtkOutputWindow.GetInstance().DisplayWarningText(
            "multichannel_explorer: %s\n" % message)
    except Exception:  # pragma: no cover - last resort
        import sys

        sys.stderr.write("multichannel_explorer: warning: %s\n" % message)


def _gui_text(title, action):
    """The text a GUI control shows for action(), which returns it: an error becomes
    "title: error" (a ValueError is the user's to fix; any other is also warned in Output
    Messages), so a click never fails silently."""
    try:
        return action()
    except ValueError as error:
        return "%s: %s" % (title, error)
    except Exception as error:  # noqa: BLE001 - shown to the user, not swallowed
        text = "%s: %s" % (title, error)
        _warn(text)
        return text


def _same_proxy(a, b):
    if a is None or b is None:
        return False
    a = getattr(a, "SMProxy", a)
    b = getattr(b, "SMProxy", b)
    return a is b or (hasattr(a, "GetGlobalID") and hasattr(b, "GetGlobalID")
                      and a.GetGlobalID() == b.GetGlobalID())


def _find_filter(source, xml_name=_FILTER_XML_NAME):
    """The filter of type `xml_name` (default BestViewpoint) already applied to `source`,
    or None."""
    simple = _simple()
    for proxy in simple.GetSources().values():
        if proxy.SMProxy.GetXMLName() != xml_name:
            continue
        inputs = proxy.Input
        if not isinstance(inputs, (list, tuple)):
            inputs = [inputs]
        for inp in inputs:
            if _same_proxy(inp, source):
                return proxy
    return None


def _is_representation(proxy):
    proxy = getattr(proxy, "SMProxy", proxy)
    return proxy is not None and proxy.GetXMLGroup() == "representations"


class _Follower(object):
    """Calls `callback` whenever a proxy property changes; stop() ends it."""

    def __init__(self, proxy, prop_name, callback):
        self.property = proxy.GetProperty(prop_name)
        if self.property is None:
            raise ValueError("%s has no property %s" % (proxy.GetXMLName(), prop_name))
        self.property = getattr(self.property, "SMProperty", self.property)
        self.callback = callback
        self.tag = self.property.AddObserver("ModifiedEvent", self._fire)
        self.busy = False

    def _fire(self, *unused):
        if self.busy:  # a change made by the callback itself
            return
        self.busy = True
        try:
            self.callback()
        finally:
            self.busy = False

    def stop(self):
        if self.tag is not None:
            self.property.RemoveObserver(self.tag)
            self.tag = None


_followers = []  # keeps observers' Python callbacks alive
