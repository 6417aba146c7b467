"""explore_multichannel and show_spectrum (what the GUI's Explore Multichannel and Show
Spectrum buttons run), and DimensionReduction's spectrum not shown by itself.

Known answers:
- small_64D.nii (65 diffusion channels in one file, 10x10x10 voxels): one multichannel
  volume, so no MergeChannels; the reduction is named "Exploration of small_64D", shown as a
  Gaussian TF Volume with 4 widgets; the reduced domain ("Reduced domain of small_64D") and
  the widget spheres in a second render view, in the same layout, in another cell; the
  camera looks along the best direction of "Best viewpoint of small_64D"; the reduction is
  the active source;
- three single-channel volumes on one grid (written here as .vti: x, y and x*y ramps)
  opened as three readers, and gather=True given the second alone: all three merged in
  their creation order ("Channels of x + y + xy"), a fourth reader on another grid left
  out;
- bad selections: nothing, one single-channel volume alone (gather off): ValueErrors that
  say what to select;
- ParaView's rule for showing the reduction's outputs (ShowInPreferredView, what Apply
  does in the GUI): the Spectrum port is shown in no view and no view is made for it;
- Show Reduced Domain (the GUI button's helper) on a Gaussian TF Volume made by hand with no
  widgets: 4 widgets seeded, "Reduced domain of by hand" and its spheres shown; pressed again:
  "already shown", no new view; on a source not shown as Gaussian TF Volume: what to select;
- show_spectrum: an XY bar chart of the Spectrum port with X = the 'index' column
  (components 1, 2, ...), not the row index, and only 'value' plotted; titles say
  component and eigenvalue, the chart title names the method, the number kept and the
  variance retained (the filter's own VarianceRetained, in percent); it opens in the
  volume view's layout (one more view there); the spectrum's X values are 1..n, the axis
  shows the 20 leading ones (520 on small_64D's 24D features).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402
import numpy as np  # noqa: E402

T.load_plugin(globals())
import multichannel_explorer as mce  # noqa: E402

C = T.Checker("test_exploration")
out = T.fresh_output_dir("exploration")


def names():
    return sorted(key[0] for key in simple.GetSources())


def xml(name):
    proxy = simple.FindSource(name)
    return proxy.GetXMLName() if proxy is not None else None


# --- one multichannel volume ----------------------------------------------------------
volume = simple.OpenDataFile(T.data_file("small_64D.nii"))
simple.RenameSource("small_64D.nii", volume)
view = simple.CreateView("RenderView")
view.ViewSize = [400, 300]
simple.AssignViewToLayout(view=view, layout=simple.CreateLayout("exploration"))
result = mce.explore_multichannel([volume], view)
C.check(result.name == "small_64D", "the exploration is named after the file: %r" % result.name)
C.check(result.merged is None and not any(xml(n) == "MergeChannels" for n in names()),
        "one multichannel volume: nothing merged")
C.check(xml("Exploration of small_64D") == "DimensionReduction" and
        simple.FindSource("Exploration of small_64D").SMProxy is result.reduction.SMProxy,
        "the reduction is 'Exploration of small_64D': %s" % names())
for piece, kind in (("Reduced domain of small_64D", "ReducedDomain"),
                    ("Widget spheres of small_64D", "Glyph"),
                    ("Best viewpoint of small_64D", "BestViewpoint")):
    C.check(xml(piece) == kind, "%r is a %s" % (piece, kind))
C.check(result.display.SMProxy.GetProperty("Representation").GetElement(0) ==
        "Gaussian TF Volume" and
        result.widgets == 4 and len(result.display.GaussianWidgets) == 32,
        "shown as Gaussian TF Volume with 4 widgets (%d)" % result.widgets)
layout = simple.GetLayout(view)
C.check(layout is not None and simple.GetLayout(result.domain_view) is not None and
        simple.GetLayout(result.domain_view).SMProxy is layout.SMProxy and
        layout.GetViewLocation(view) != layout.GetViewLocation(result.domain_view),
        "the domain view beside the volume view, in its layout")
shown = [servermanager.ProxyManager().GetProxyName("sources", r.Input.SMProxy)
         for r in result.domain_view.Representations
         if r.GetProperty("Input") is not None and r.Visibility]
C.check(sorted(shown) == ["Reduced domain of small_64D", "Widget spheres of small_64D"],
        "... showing the domain and the widget spheres: %s" % shown)
best = result.viewpoint
if C.check(best.valid, "a best view was found"):
    d = T.camera_direction(view)
    C.check(abs(T.dot(T.unit(d), T.unit(best.direction))) > 0.9999,
            "the camera looks along it (%s vs %s)" % (d, best.direction))
C.check(simple.GetActiveSource().SMProxy is result.reduction.SMProxy,
        "the reduction is the active source")

# --- the Spectrum port is shown in no view by ParaView's Apply rule ---------------------
controller = servermanager.vtkSMParaViewPipelineControllerWithRendering()
views_before = len(simple.GetViews())
shown_in = controller.ShowInPreferredView(result.reduction.SMProxy, 1, view.SMProxy)
C.check(shown_in is None and len(simple.GetViews()) == views_before and
        view.SMProxy.FindRepresentation(result.reduction.SMProxy, 1) is None,
        "Apply's rule shows the Spectrum port nowhere and makes no view for it "
        "(views %d -> %d)" % (views_before, len(simple.GetViews())))

# --- show_spectrum -------------------------------------------------------------------------
chart, bars = mce.show_spectrum(result.display, view)
C.check(chart.GetXMLName() == "XYBarChartView", "show_spectrum opens a bar chart")
C.check(int(bars.UseIndexForXAxis) == 0 and bars.XArrayName == "index",
        "X is the component number (the 'index' column), not the row index")
visible = list(bars.SeriesVisibility)
C.check(visible == ["value"], "only the eigenvalues are plotted: %s" % visible)
C.check(chart.BottomAxisTitle == "Component" and chart.LeftAxisTitle.startswith("Eigenvalue"),
        "axes: %r, %r" % (chart.BottomAxisTitle, chart.LeftAxisTitle))
result.reduction.UpdatePropertyInformation()
variance = float(result.reduction.GetProperty("VarianceRetained")[0])
# DimensionReduction's default method is PCA.
expected = "PCA spectrum: 3 components kept, %.0f%% of the variance" % (100 * variance)
C.check(chart.ChartTitle == expected, "title %r (expected %r)" % (chart.ChartTitle, expected))
C.check(simple.GetLayout(chart) is not None and
        simple.GetLayout(chart).SMProxy is layout.SMProxy,
        "the chart opens in the volume view's layout")
table = result.reduction.GetClientSideObject().GetOutputDataObject(1)
index = [table.GetColumnByName("index").GetValue(i) for i in range(table.GetNumberOfRows())]
C.check(index == list(range(1, len(index) + 1)) and len(index) >= 3,
        "the X values are the components 1..%d" % len(index))
C.check(int(chart.BottomAxisUseCustomRange) == 1 and chart.BottomAxisRangeMinimum == 0.5 and
        chart.BottomAxisRangeMaximum == 20.5,
        "the X axis on the 20 leading components of %d" % len(index))
simple.SaveScreenshot(os.path.join(out, "spectrum.png"), chart, ImageResolution=[500, 300])

# --- three single-channel files on one grid, gathered from one -----------------------------
z, y, x = np.mgrid[0:12, 0:14, 0:16].astype(np.float32)
files = []
for name, values in (("x", x), ("y", y), ("xy", x * y + 3 * np.sin(z))):
    files.append(T.write_vti(os.path.join(out, name + ".vti"), [(name, values)]))
T.write_vti(os.path.join(out, "other.vti"), [("other", x[:, :, :8])])
readers = []
for path in files + [os.path.join(out, "other.vti")]:
    reader = simple.OpenDataFile(path)
    simple.RenameSource(os.path.basename(path), reader)
    readers.append(reader)
view2 = simple.CreateView("RenderView")
view2.ViewSize = [300, 200]
simple.AssignViewToLayout(view=view2, layout=simple.CreateLayout("gathered"))
gathered = mce.explore_multichannel([readers[1]], view2, widgets=2, gather=True)
C.check(gathered.name == "x + y + xy",
        "one single-channel reader gathers the other unused ones on its grid, in creation "
        "order: %r" % gathered.name)
merged_inputs = [servermanager.ProxyManager().GetProxyName("sources", p.SMProxy)
                 for p in gathered.merged.Input] if gathered.merged is not None else []
C.check(xml("Channels of x + y + xy") == "MergeChannels" and
        merged_inputs == ["x.vti", "y.vti", "xy.vti"],
        "... merged as 'Channels of x + y + xy' from %s (other.vti, on another grid, left out)"
        % merged_inputs)
C.check(gathered.widgets == 2, "... 2 widgets asked, 2 seeded (%d)" % gathered.widgets)

# --- bad selections ----------------------------------------------------------------------------
for sources, words, label in (([], "select the channel readers", "nothing selected"),
                              ([readers[3]], "has one channel", "one lone channel")):
    try:
        mce.explore_multichannel(sources, view2)
        C.check(False, "%s: an error" % label)
    except ValueError as error:
        C.check(words in str(error), "%s: %s" % (label, error))

# --- Show Reduced Domain on a Gaussian TF Volume made by hand, without widgets -----------------
wavelet = simple.Wavelet(WholeExtent=[-8, 8, -8, 8, -8, 8])
coords = simple.Calculator(Input=wavelet, Function="coords", ResultArrayName="ReducedCoordinates",
                           ResultArrayType="Float")
simple.RenameSource("by hand", coords)
view3 = simple.CreateView("RenderView")
view3.ViewSize = [300, 200]
simple.AssignViewToLayout(view=view3, layout=simple.CreateLayout("by hand"))
hand = mce.show_gaussian_tf(coords, view3)
simple.SetActiveView(view3)
simple.SetActiveSource(coords)
text = mce.exploration._gui_show_domain()
C.check(text.startswith("Reduced domain of by hand opened") and
        xml("Reduced domain of by hand") == "ReducedDomain" and
        xml("Widget spheres of by hand") == "Glyph",
        "Show Reduced Domain: %r" % text)
C.check(len(hand.GaussianWidgets) == 32, "... seeded 4 widgets first (the display had none): %d"
        % (len(hand.GaussianWidgets) // 8))
views = len(simple.GetViews())
text = mce.exploration._gui_show_domain()
C.check("already shown" in text and len(simple.GetViews()) == views,
        "a second press opens no second domain view: %r" % text)
simple.SetActiveSource(wavelet)
text = mce.exploration._gui_show_domain()
C.check(text.startswith("Show Reduced Domain: select a volume shown as Gaussian TF Volume"),
        "on a source not shown as Gaussian TF Volume: %r" % text)
C.finish()
