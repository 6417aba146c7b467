"""Runs a Python state file in this (fresh) pvbatch and writes what it built as JSON:
  pvbatch gui_save_state_load.py STATE.py OUT.json
{"error": the exception's text or null, "sources": {name: [xml name, [input names]]},
 "reduction": {"points": N, "components": C} of the first DimensionReduction's
 ReducedCoordinates after an update, "plugin_loaded": the plugin's filters exist in the
 state's namespace or in paraview.simple}. The plugin is not preloaded (no PV_PLUGIN_PATH): only the state can
load it."""
import json
import os
import sys
import traceback

from paraview import servermanager, simple

state_path, out_path = sys.argv[1], sys.argv[2]
result = {"error": None, "sources": {}, "reduction": None,
          "preloaded": hasattr(simple, "DimensionReduction")}
# The state's LoadPlugin(..., ns=globals()) puts the plugin's proxies here.
namespace = {"__name__": "__main__"}
try:
    with open(state_path) as f:
        code = f.read()
    exec(compile(code, state_path, "exec"), namespace)
except Exception:  # noqa: BLE001 (the caller checks the text)
    result["error"] = traceback.format_exc()
pxm = servermanager.ProxyManager()
for (name, _), proxy in simple.GetSources().items():
    inputs = []
    prop = proxy.SMProxy.GetProperty("Input")
    if prop is not None:
        inputs = [pxm.GetProxyName("sources", prop.GetProxy(i))
                  for i in range(prop.GetNumberOfProxies())]
    result["sources"][name] = [proxy.GetXMLName(), inputs]
    if proxy.GetXMLName() == "DimensionReduction" and result["reduction"] is None:
        proxy.UpdatePipeline()
        info = proxy.GetDataInformation()
        array = proxy.PointData["ReducedCoordinates"] if "ReducedCoordinates" in \
            proxy.PointData.keys() else None
        result["reduction"] = {"points": info.GetNumberOfPoints(),
                               "components": array.GetNumberOfComponents() if array else 0}
result["plugin_loaded"] = "DimensionReduction" in namespace or hasattr(simple,
                                                                       "DimensionReduction")
with open(out_path, "w") as f:
    json.dump(result, f, indent=1)
sys.stdout.flush()
os._exit(0)
