"""The plugin in pvpython (client + built-in server): LoadPlugin, the proxies exist, the
Python module imports, the filter runs on a Wavelet, Device=GPU falls back (or runs)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_load_pvpython")
pxm = servermanager.ProxyManager()
for group, name in (("filters", "BestViewpoint"), ("sources", "VolPackDenReader"),
                    ("sources", "NIfTIImageReader")):
    C.check(pxm.SMProxyManager.GetPrototypeProxy(group, name) is not None,
            "proxy %s/%s defined" % (group, name))
C.check(callable(mce.apply_best_viewpoint), "multichannel_explorer.apply_best_viewpoint")
import multichannel_explorer.viewpoint  # noqa: E402

C.check(multichannel_explorer.viewpoint.apply_best_viewpoint is mce.apply_best_viewpoint,
        "import multichannel_explorer.viewpoint (a module of the embedded package)")
w = Wavelet(WholeExtent=[-16, 16, -16, 16, -16, 16])
bvp = BestViewpoint(Input=w, Device="GPU")
msgs = T.Messages(bvp)
bvp.UpdatePipeline()
bvp.UpdatePropertyInformation()
device = bvp.GetPropertyValue("DeviceUsed")
C.check(int(bvp.GetPropertyValue("ViewValid")) == 1, "BestViewpoint runs in pvpython")
C.check(device == "GPU" or msgs.any_warning("GPU"),
        "Device=GPU: ran on %s%s" % (device, " with a fallback warning" if device != "GPU" else ""))
print("warnings:", msgs.warnings)
C.finish()
