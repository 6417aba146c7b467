"""GUI test "ParaView's own Save State (.py) loads the plugin", part 1 (run by
`paraview --script=` with the plugin auto-loaded from PV_PLUGIN_PATH, before
gui_save_state_click.xml applies Filters > Multichannel > DimensionReduction and saves the
state through File > Save State as a .py file). Opens small_64D.nii (65 channels) as the
active source and records into $MCV_GUI_STATE the reader's name and type and the state
file's path. Nothing here imports multichannel_explorer: only the plugin's loading can
have installed the state hook."""
import json
import os
import sys

from paraview.simple import *  # noqa: F401,F403

data = os.environ.get("MCV_DATA_DIR", "")
out = os.environ.get("MCV_OUTPUT_DIR", ".")
state_file = os.environ.get("MCV_GUI_STATE") or os.path.join(out, "gui_save_state_state.json")
path = os.path.join(data, "small_64D.nii")
saved = os.path.join(out, "gui_save_state.py")
if os.path.exists(saved):
    os.remove(saved)
state = {"data": os.path.exists(path), "saved": saved}
if state["data"]:
    reader = OpenDataFile(path)
    view = GetActiveViewOrCreate("RenderView")
    Show(reader, view)
    Render(view)
    SetActiveSource(reader)
    pxm = servermanager.ProxyManager()
    state["reader"] = [pxm.GetProxyName("sources", reader.SMProxy), reader.GetXMLName()]
    state["points"] = reader.GetDataInformation().GetNumberOfPoints()
with open(state_file, "w") as f:
    json.dump(state, f, indent=1)
