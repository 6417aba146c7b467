"""GUI test of the Gaussian widget handles in the reduced-domain view, part 1 (run by
`paraview --script=` before gui_handles_click.xml drags the handles with recorded mouse
events). A synthetic volume whose ReducedCoordinates are the voxel positions (so the
reduced domain is the cube [-10, 10]^3) is shown as a Gaussian TF Volume with 3 widgets,
widget 1 at the domain's centre; show_dual_domain puts the domain view beside it, whose
camera is set to a known parallel projection looking down -z (ParallelScale 12, the
focal point at the origin): widget 1's centre is then at the middle of the view, and a
drag of n pixels is n * 2 * 12 / (view height) domain units.

Recorded into $MCV_GUI_STATE for gui_handles_check.py: the widgets at the start, every
change of the display's GaussianWidgets (with the domain view's size and camera), the
undo stack's labels after every push. After the second undo set (the second drag) a
screenshot of the whole window is taken: gui_handles_window.png."""
import os

from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce
import gui_setup as G

window_png = G.removed(os.path.join(G.output_dir(), "gui_handles_window.png"))

wavelet = Wavelet(WholeExtent=[-10, 10, -10, 10, -10, 10])
coords = Calculator(Input=wavelet, Function="coords", ResultArrayName="ReducedCoordinates",
                    ResultArrayType="Float")
view = GetActiveViewOrCreate("RenderView")
view.OrientationAxesVisibility = 0
widgets = [0, 0, 0, 2.5, 1, 0.1, 0.1, 1,       # 1: red, at the centre (dragged)
           -6, -6, 0, 2.0, 0.1, 0.8, 0.1, 1,   # 2: green
           6, -6, 0, 2.0, 0.2, 0.3, 1, 1]      # 3: blue
display = mce.show_gaussian_tf(coords, view, widgets=widgets)
view.CameraPosition = [0, 0, 60]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 1, 0]
Render(view)

dual = mce.show_dual_domain(display, view, sample_size=3000)
domain_view = dual.domain_view
domain_view.OrientationAxesVisibility = 0
domain_view.CameraParallelProjection = 1
domain_view.CameraPosition = [0, 0, 50]
domain_view.CameraFocalPoint = [0, 0, 0]
domain_view.CameraViewUp = [0, 1, 0]
domain_view.CameraParallelScale = 12
Render(domain_view)
SetActiveView(domain_view)

state = G.State("handles", initial=[float(v) for v in display.GaussianWidgets],
                changes=[], undo=[], screenshot=window_png)
save = state.save


def on_widgets(*unused):
    state["changes"].append({
        "values": [float(v) for v in display.GaussianWidgets],
        "view_size": [int(v) for v in domain_view.ViewSize],
        "parallel_scale": float(domain_view.CameraParallelScale),
        "parallel": int(domain_view.CameraParallelProjection),
        "position": [float(v) for v in domain_view.CameraPosition],
        "focal_point": [float(v) for v in domain_view.CameraFocalPoint]})
    save()


display.GetProperty("GaussianWidgets").SMProperty.AddObserver("ModifiedEvent", on_widgets)

stack = servermanager.vtkSMProxyManager.GetProxyManager().GetUndoStackBuilder().GetUndoStack()


def on_undo_stack(*unused):
    # Only the top labels: the stack keeps at most its depth (10) of sets.
    labels = [stack.GetUndoSetLabel(i) for i in range(min(3, stack.GetNumberOfUndoSets()))]
    state["undo"].append({"labels": labels, "changes_so_far": len(state["changes"])})
    save()
    if labels and labels[0].startswith("Resize Gaussian Widget") and \
            not state.get("screenshot_requested"):
        # The second drag ended: the whole window a moment later (the click script keeps
        # the event loop running meanwhile, so the views are drawn).
        state["screenshot_requested"] = True
        save()
        G.screenshot(window_png)


stack.AddObserver("ModifiedEvent", on_undo_stack)
save()
