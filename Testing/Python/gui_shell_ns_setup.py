"""GUI test "the helpers in the GUI's Python shell, plugin loaded with ns=", part 1 (run by
`paraview --script=`, the GUI's own Python, without PV_PLUGIN_PATH): the plugin is loaded
as the README writes it, LoadPlugin(path, ns=globals()), which puts its filters into this
namespace and not into paraview.simple's; then every public helper of
multichannel_explorer is called on the real 3-channel brain. Each call's outcome (ok, or
the exception's text) is recorded into $MCV_GUI_STATE for gui_shell_ns_check.py."""
import os
import traceback

from paraview import simple
from paraview.simple import *  # noqa: F401,F403
import gui_setup as G

out = G.output_dir()
state = G.State("shell_ns", events=[])
save = state.save


def step(name, call, expect=lambda result: True):
    """Runs call(); records ok (the call returned and its result is as expected, with a
    short repr of it) or the error."""
    try:
        result = call()
        state["events"].append({"step": name, "ok": bool(expect(result)),
                                "result": repr(result)[:200]})
        save()
        return result
    except Exception:  # noqa: BLE001 (the test reports every failure)
        state["events"].append({"step": name, "ok": False, "error": traceback.format_exc()})
        save()
        return None


state["autoloaded"] = hasattr(simple, "DimensionReduction")
LoadPlugin(os.environ["MCV_PLUGIN"], remote=False, ns=globals())
state["in_namespace"] = all(name in globals() for name in (
    "MergeChannels", "MultichannelFeatures", "DimensionReduction", "BestViewpoint",
    "ReducedDomain"))
save()
import multichannel_explorer as mx  # noqa: E402

channels = [OpenDataFile(G.data_path(n))
            for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
volume = MergeChannels(Input=channels)  # noqa: F405 (from the plugin, through ns=)
view = GetActiveViewOrCreate("RenderView")
pair = step("reduce_multichannel", lambda: mx.reduce_multichannel(
    volume, "PCA", "6D", ReferenceSampleSize=3000))
reduction = pair[1] if pair else None


def domain_points():
    domain = mx.reduced_domain_filter(reduction, SampleSize=500)
    domain.UpdatePipeline()
    return domain.GetDataInformation().GetNumberOfPoints()


step("reduced_domain_filter", domain_points, lambda n: n == 500)
display = step("show_gaussian_tf", lambda: mx.show_gaussian_tf(reduction, view))
step("auto_widgets", lambda: len(mx.auto_widgets(display, 3)) // 8, lambda n: n == 3)
dual = step("show_dual_domain", lambda: mx.show_dual_domain(display, view))
step("best_viewpoint_filter", lambda: mx.best_viewpoint_filter(reduction, view)
     .GetPropertyValue("ViewValid"), lambda valid: valid == 1)
step("apply_best_viewpoint", lambda: mx.apply_best_viewpoint(reduction, view).valid,
     lambda valid: valid)
step("follow_best_viewpoint", lambda: mx.follow_best_viewpoint(display, view) is not None)
step("stop_following", mx.stop_following)
hit = step("probe", lambda: mx.probe(display, (90, 108, 90)),
           lambda h: tuple(h.index) == (90, 108, 90) and len(h.coordinates) == 3)
step("add_widget_at", lambda: mx.add_widget_at(display, hit),
     lambda unused: len(display.GaussianWidgets) == 4 * 8)
step("probe_at_pixel", lambda: mx.probe_at_pixel(view, 150, 150))
step("brush", lambda: mx.brush(display, box=(-1, 1, -1, 1, -1, 1)), lambda n: n > 0)
state["done"] = True
save()
SaveScreenshot(os.path.join(out, "gui_shell_ns.png"), view)
