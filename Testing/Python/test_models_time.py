"""Saving a reduction model of a time series saves the fit of the step on screen.

With FitTime "Each time step" (the default) every step of a series has its own fit. A
proxy's UpdatePipeline() without a time, and a new writer's, re-run at the time last asked
of the reduction: save_model (and save_transfer_function, which writes the model beside
its widgets, and the editor's Save...) wrote the model of whatever step the reduction had
last computed, so applied again it gave other coordinates than the ones on screen.

Known answers, on three steps of the real brain (T1 + AAL every 4th voxel; the T1 of
step t brightened by 40 t % in its upper half, so that each step has its own fit), with
the view at step t and the reduction last updated at another step:
- the model save_model writes, applied to the series (ModelFile) at step t, gives step
  t's on-screen coordinates bit for bit; the three steps' models differ (crc32);
- so does the model save_transfer_function writes beside the widgets;
- show_spectrum updates the reduction at step t: its VarianceRetained is step t's;
- explore_multichannel with the view at step 1 runs its reduction once, at step 1.
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
import numpy as np  # noqa: E402
from paraview import servermanager, simple  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

C = T.Checker("test_models_time")
OUT = os.path.join(T.output_dir(), "models_time")
if os.path.isdir(OUT):
    shutil.rmtree(OUT)
os.makedirs(OUT)

brain = T.brain_arrays(("ch2", "aal"), step=4).astype(np.float32)
t1, aal = brain[0], brain[1]
files = []
for step in range(3):
    bright = t1.copy()
    bright[t1.shape[0] // 2:] *= 1.0 + 0.4 * step
    files.append(T.write_vti(os.path.join(OUT, "step_%d.vti" % step),
                             [("ch2", bright), ("aal", aal)]))

series, times, scene = T.open_series(files, C)
view = T.render_view([200, 200])
simple.SetActiveView(view)
_, reduction = mce.reduce_multichannel(series, "PCA", "6D", ReferenceSampleSize=2000)
display = mce.show_gaussian_tf(reduction, view, widgets=[0, 0, 0, 1, 1, 0, 0, 0.5])


def coordinates(proxy, time):
    proxy.UpdatePipeline(time)
    array = servermanager.Fetch(proxy).GetPointData().GetArray("ReducedCoordinates")
    return vtk_to_numpy(array).copy()


def difference(model, step, on_screen):
    """The largest difference between the coordinates `model` gives step `step` and
    `on_screen` (inf: another shape)."""
    _, applied = mce.reduce_multichannel(series, model=model)
    got = coordinates(applied, times[step])
    simple.Delete(applied)
    return float(np.abs(got - on_screen).max()) if got.shape == on_screen.shape else np.inf


def variance_retained(time):
    reduction.UpdatePipeline(time)
    reduction.UpdatePropertyInformation()
    return float(reduction.GetPropertyValue("VarianceRetained"))


crcs = {}
for shown in (2, 0, 1):
    scene.AnimationTime = times[shown]
    simple.Render(view)
    on_screen = coordinates(reduction, times[shown])
    variance = variance_retained(times[shown])
    other = times[(shown + 1) % 3]
    reduction.UpdatePipeline(other)  # the time last asked of it: another step

    path = mce.save_model(reduction, os.path.join(OUT, "shown_%d.mcvmodel" % shown))
    crcs[shown] = int(mce.read_model(path)["crc32"])
    worst = difference(path, shown, on_screen)
    C.check(worst == 0, "step %d on screen, the reduction last at another step: save_model's "
            "model gives step %d's coordinates bit for bit (largest difference %.3g)"
            % (shown, shown, worst))

    reduction.UpdatePipeline(other)
    folder = os.path.join(OUT, "tf_%d" % shown)
    os.makedirs(folder)
    mce.save_transfer_function(display, os.path.join(folder, "widgets.mcvtf"))
    worst = difference(os.path.join(folder, "widgets.mcvmodel"), shown, on_screen)
    C.check(worst == 0, "step %d: save_transfer_function writes step %d's fit beside the "
            "widgets (its coordinates bit for bit; largest difference %.3g)"
            % (shown, shown, worst))

    reduction.UpdatePipeline(other)
    chart, _ = mce.show_spectrum(reduction, view)
    spectrum_variance = float(reduction.GetPropertyValue("VarianceRetained"))
    simple.Delete(chart)
    simple.SetActiveView(view)
    C.check(spectrum_variance == variance,
            "step %d: show_spectrum shows step %d's fit (variance retained %.6f, the "
            "step's own %.6f)" % (shown, shown, spectrum_variance, variance))

# explore_multichannel at step 1: one reduction run, at step 1 (a new filter updated
# without a time ran the first step, then the view ran step 1 again: twice the work).
import multichannel_explorer.exploration as exploration  # noqa: E402
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline  # noqa: E402

runs = []
plain_filter = exploration._filter


def observed_filter(name):
    """The exploration's filter constructors; a DimensionReduction notes the time step
    of each of its runs (None: no time asked)."""
    ctor = plain_filter(name)
    if name != "DimensionReduction":
        return ctor

    def make(**props):
        proxy = ctor(**props)

        def started(algorithm, event):
            info = algorithm.GetOutputInformation(0)
            key = vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP()
            runs.append(info.Get(key) if info.Has(key) else None)

        proxy.GetClientSideObject().AddObserver("StartEvent", started)
        return proxy
    return make


exploration._filter = observed_filter
scene.AnimationTime = times[1]
explored = mce.explore_multichannel([series], view, widgets=2)
exploration._filter = plain_filter
C.check(runs == [times[1]], "explore_multichannel at step 1 reduces step 1 once (runs at %s)"
        % runs)

C.check(len(set(crcs.values())) == 3,
        "each step has its own fit: three different models %s"
        % ["%08x" % crcs[s] for s in sorted(crcs)])
C.finish()
