"""GUI test "ParaView's own Save State (.py) loads the plugin", part 1 (run by
`paraview --script=` with the plugin auto-loaded from PV_PLUGIN_PATH, before
gui_save_state_click.xml applies Filters > Multichannel > DimensionReduction and saves the
state through File > Save State as a .py file). Opens small_64D.nii (65 channels) as the
active source and records into $MCV_GUI_STATE the reader's name and type and the state
file's path. Nothing here imports multichannel_explorer: only the plugin's loading can
have installed the state hook."""
import os

from paraview.simple import *  # noqa: F401,F403
import gui_setup as G

saved = G.removed(os.path.join(G.output_dir(), "gui_save_state.py"))
state = G.State("save_state", saved=saved)
reader = G.open_active("small_64D.nii", state)
if reader is not None:
    pxm = servermanager.ProxyManager()
    state["reader"] = [pxm.GetProxyName("sources", reader.SMProxy), reader.GetXMLName()]
    state["points"] = reader.GetDataInformation().GetNumberOfPoints()
state.save()
