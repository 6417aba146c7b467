"""GUI test of DimensionReduction's spectrum, part 1 (run by `paraview --script=` before
gui_spectrum_click.xml applies Filters > Multichannel > DimensionReduction with the
Properties panel's Apply, then Filters > Multichannel > Show Spectrum): opens small_64D.nii
(65 channels) as the active source, and wraps the button's helper to record, into
$MCV_GUI_STATE, the views before and after it (types, what each shows) and its text."""
import json
import os

from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer.exploration as exploration

data = os.environ.get("MCV_DATA_DIR", "")
out = os.environ.get("MCV_OUTPUT_DIR", ".")
state_file = os.environ.get("MCV_GUI_STATE") or os.path.join(out, "gui_spectrum_state.json")
path = os.path.join(data, "small_64D.nii")
state = {"data": os.path.exists(path)}


def save():
    with open(state_file, "w") as f:
        json.dump(state, f, indent=1)


def views():
    pxm = servermanager.ProxyManager()
    found = []
    for view in GetViews():
        shown = []
        for rep in view.Representations:
            prop = rep.SMProxy.GetProperty("Input")
            if prop is None or not rep.Visibility or not prop.GetNumberOfProxies():
                continue
            shown.append([pxm.GetProxyName("sources", prop.GetProxy(0)),
                          prop.GetOutputPortForConnection(0)])
        found.append({"type": view.GetXMLName(), "shown": shown})
    return found


if state["data"]:
    reader = OpenDataFile(path)
    view = GetActiveViewOrCreate("RenderView")
    Show(reader, view)
    Render(view)
    SetActiveSource(reader)
_helper = exploration._gui_show_spectrum


def show_spectrum():
    state["before"] = views()
    text = _helper()
    state.update(text=text, after=views())
    chart = [v for v in GetViews() if v.GetXMLName() == "XYBarChartView"]
    if chart:
        bars = [r for r in chart[0].Representations if r.Visibility]
        def strings(proxy, name):
            prop = proxy.SMProxy.GetProperty(name)
            return [str(prop.GetElement(i)) for i in range(prop.GetNumberOfElements())]

        state["chart"] = {"title": str(chart[0].ChartTitle),
                          "x": strings(bars[0], "XArrayName")[0] if bars else None,
                          "index_for_x": int(bars[0].UseIndexForXAxis) if bars else None,
                          "series": strings(bars[0], "SeriesVisibility") if bars else None}
    save()
    return text


exploration._gui_show_spectrum = show_spectrum
save()
