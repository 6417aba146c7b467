"""GUI test of DimensionReduction's spectrum, part 1 (run by `paraview --script=` before
gui_spectrum_click.xml applies Filters > Multichannel > DimensionReduction with the
Properties panel's Apply, then Filters > Multichannel > Show Spectrum): opens small_64D.nii
(65 channels) as the active source, and wraps the button's helper to record, into
$MCV_GUI_STATE, the views before and after it (types, what each shows) and its text."""
from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer.exploration as exploration
import gui_setup as G

state = G.State("spectrum")
save = state.save
reader = G.open_active("small_64D.nii", state)


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
