"""GUI test, part 1 (run by `paraview --script=` before the XML test script clicks the
toolbar button): open brainsmall.den, show it as a volume, make it the active source,
and record what the button's Python call does into $MCV_GUI_STATE
(apply_best_viewpoint is wrapped, not replaced). test_gui.sh checks that file with gui_best_viewpoint_check.py."""
import os

from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce
import gui_setup as G

out = G.output_dir()
reader = OpenDataFile(G.data_path("brainsmall.den"))
view = GetActiveViewOrCreate("RenderView")
display = Show(reader, view)
display.SetRepresentationType("Volume")
Render(view)
SetActiveSource(reader)
state = G.State("best_viewpoint", loaded=reader.GetXMLName(),
                before=[float(x) for x in view.CameraPosition])
state.save()

_original = mce.apply_best_viewpoint


def _recording(*args, **kwargs):
    result = _original(*args, **kwargs)
    v = args[1] if len(args) > 1 else kwargs.get("view")
    state.update(
        called=True, kwargs=sorted(kwargs), valid=bool(result.valid),
        direction=result.direction, best=result.best, view_up=result.view_up,
        entropies=result.entropies,
        opacity_from_display=result.filter.OpacityFunction is not None,
        camera_position=[float(x) for x in v.CameraPosition],
        camera_focal_point=[float(x) for x in v.CameraFocalPoint],
        camera_view_up=[float(x) for x in v.CameraViewUp])
    SaveScreenshot(os.path.join(out, "gui_after_button.png"), v)
    state.save()
    return result


mce.apply_best_viewpoint = _recording
