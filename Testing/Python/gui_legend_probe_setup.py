"""GUI test: the probe's label covers neither the widget legend nor the orientation axes,
part 1 (run by `paraview --script=` before gui_legend_probe_click.xml switches Probe on
and clicks the middle of the volume view, then low in it, where the label first sits).

A synthetic volume with known ReducedCoordinates (0.1 of the voxel position), small in the
middle of a magenta view, is shown as a Gaussian TF Volume with one opaque widget whose
long name makes the legend wide (as atlas region names do), in a view about 600 pixels
wide, with ParaView's orientation axes at the bottom left (shown, as by default). The
probe's label is a dark box over the view, the legend a dark translucent box: over
magenta they have colours no other part of the window has, (71, 16, 71) and
(102, 13, 102). probe_at_pixel is wrapped to record the probe, and a screenshot of the
whole window is taken 2 s after it, once the label is shown: gui_legend_probe_window.png
after the first, gui_legend_probe_low.png after the second, which
gui_legend_probe_check.py reads."""
import os

from paraview.simple import *  # noqa: F401,F403
import multichannel_explorer as mce
import gui_setup as G

out = G.output_dir()
window_png = G.removed(os.path.join(out, "gui_legend_probe_window.png"))
low_png = G.removed(os.path.join(out, "gui_legend_probe_low.png"))
state = G.State("legend_probe", events=[], screenshot=window_png, screenshot_low=low_png,
                widget_name="Frontal_Inf_Orb_L, Frontal_Inf_Tri_L and Frontal_Inf_Oper_L (AAL)")

wavelet = Wavelet(WholeExtent=[-10, 10, -10, 10, -6, 6])
coords = Calculator(Input=wavelet, ResultArrayName="ReducedCoordinates", ResultArrayType="Float",
                    Function="0.1*coords")
coords.UpdatePipeline()
view = GetActiveViewOrCreate("RenderView")
view.OrientationAxesVisibility = 1  # ParaView's default: the label must keep off them
view.UseColorPaletteForBackground = 0
view.Background = [1.0, 0.0, 1.0]
# One opaque widget over the whole volume, cyan: far from the boxes' colours.
display = mce.show_gaussian_tf(coords, view, widgets=[0, 0, 0, 50.0, 0.1, 0.8, 0.8, 1.0])
display.GaussianWidgetNames = [state["widget_name"]]
Render(view)
b = coords.GetDataInformation().GetBounds()
c = [(b[2 * a] + b[2 * a + 1]) / 2.0 for a in range(3)]
view.CameraFocalPoint = c
view.CameraPosition = [c[0], c[1], c[2] + 100.0]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 1
view.CameraParallelScale = 3.0 * (b[3] - b[2])  # the volume: a third of the view's height
Render(view)
SetActiveView(view)
SetActiveSource(coords)

_probe_at_pixel = mce.probe_at_pixel


def probe_at_pixel(v, x, y, *args, **kwargs):
    hit = _probe_at_pixel(v, x, y, *args, **kwargs)
    state["events"].append({"event": "probe", "pixel": [x, y],
                            "view_size": [int(s) for s in v.ViewSize],
                            "point_id": hit.point_id if hit else None})
    state.save()
    G.screenshot(window_png if len(state["events"]) == 1 else low_png)
    return hit


mce.probe_at_pixel = probe_at_pixel
state.save()
