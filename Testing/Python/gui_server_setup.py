"""GUI test of the exploration loop with the GUI connected to an MPI pvserver, part 1 (run
by `paraview --script=` in the session test_gui_server.sh starts: once built-in, once
connected with --server-url to `mpiexec -n 2 pvserver`; the plugin auto-loaded on both
sides from PV_PLUGIN_PATH).

The scene, the wrapped helpers and their expected answers are gui_probe_setup.py's (a
synthetic volume whose ReducedCoordinates are 0.1 x its voxel position, shown as a
Gaussian TF Volume beside its reduced domain; probe_at_pixel, probe_domain_at_pixel,
add_widget_at and brush record what they returned and what the data says they should):
this file runs it, then also records

- the session: remote or built-in, the number of server processes, where the plugin is
  loaded (client, server);
- every change of the display's GaussianWidgets (the editor's edit, Add Widget Here, the
  handle drag, its undo),

into $MCV_GUI_STATE for gui_server_check.py, which compares the two sessions."""
import os

from paraview import servermanager

# No __file__ in a --script: the driver names this folder.
with open(os.path.join(os.environ["MCV_TESTING_DIR"], "gui_probe_setup.py")) as f:
    exec(compile(f.read(), "gui_probe_setup.py", "exec"))

connection = servermanager.ActiveConnection
manager = servermanager.vtkSMProxyManager.GetProxyManager().GetPluginManager()


def _plugin_loaded(info):
    return any(info.GetPluginName(i) == "MultichannelExplorer" and info.GetPluginLoaded(i)
               for i in range(info.GetNumberOfPlugins() if info is not None else 0))


state["session"] = {
    "remote": bool(connection.IsRemote()),
    "uri": connection.GetURI(),
    "server_processes": int(connection.GetNumberOfDataPartitions()),
    "plugin_on_client": _plugin_loaded(manager.GetLocalInformation()),
    "plugin_on_server": _plugin_loaded(manager.GetRemoteInformation(connection.Session))
    if connection.IsRemote() else None,
}
state["widget_changes"] = []


def on_widgets(*unused):
    state["widget_changes"].append({
        "values": [float(v) for v in display.GaussianWidgets],
        "hidden": [float(v) for v in display.GaussianWidgetsHidden]})
    save()


display.GetProperty("GaussianWidgets").SMProperty.AddObserver("ModifiedEvent", on_widgets)

# gui_probe_setup.py's expected voxel of the volume-view probe is a point id of the fetched
# volume: on a server of several processes Fetch appends the pieces, so that id is no
# global voxel id. The expected voxel's position names its global id (the Wavelet's grid:
# origin 0, spacing 1).
_recorded_probe_at_pixel = mce.probe_at_pixel


def probe_at_pixel_global(v, x, y, *args, **kwargs):
    hit = _recorded_probe_at_pixel(v, x, y, *args, **kwargs)
    event = state["events"][-1]
    if event.get("expected_id") is not None:
        ext = volume.GetDataInformation().GetExtent()
        point = servermanager.Fetch(volume).GetPoint(event["expected_id"])
        ijk = [int(round(point[a])) - ext[2 * a] for a in range(3)]
        nx, ny = ext[1] - ext[0] + 1, ext[3] - ext[2] + 1
        event["expected_fetched_point_id"] = event["expected_id"]
        event["expected_id"] = ijk[0] + nx * (ijk[1] + ny * ijk[2])
        save()
    return hit


mce.probe_at_pixel = probe_at_pixel_global
state["initial_widgets"] = [float(v) for v in display.GaussianWidgets]
save()
