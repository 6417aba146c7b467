"""A first exploration in one call: channels merged when they come from several files,
features computed and reduced (DimensionReduction with its defaults), the volume shown as a
"Gaussian TF Volume" with seeded widgets, its reduced domain beside it, the camera at the
best view. Also the eigenvalue spectrum as a bar chart, on request.

The GUI's "Explore Multichannel" button (pqExploreMultichannelActions.cxx) runs the same
steps one at a time through ``_gui_begin`` / ``_gui_step``, so that it can say in the status
bar what is running; scripts call ``explore_multichannel``::

    readers = [OpenDataFile(p) for p in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
    result = mce.explore_multichannel(readers)
    print(result.name, result.widgets)       # "ch2 + aal + brodmann", 4
"""

import os
import re

from ._common import _filter, _gui_text, _same_proxy, _simple, _view_time, _warn

__all__ = [
    "explore_multichannel",
    "exploration_name",
    "show_spectrum",
]

# File endings dropped from a reader's name to name the exploration ("ch2.nii.gz" -> "ch2").
_ENDINGS = (".nii.gz", ".nii", ".ome.zarr", ".zarr", ".ome.tiff", ".ome.tif", ".tiff", ".tif",
            ".mhd", ".mha", ".den", ".vti")


def _registered_name(proxy):
    from paraview import servermanager

    name = servermanager.ProxyManager().GetProxyName("sources", proxy)
    return name or proxy.GetXMLLabel()


def _file_name(proxy):
    """The one file a reader reads, or None."""
    for prop in ("FileNames", "FileName"):
        if proxy.GetProperty(prop) is not None:
            value = proxy.GetPropertyValue(prop)
            files = [value] if isinstance(value, str) else list(value or [])
            if len(files) == 1 and files[0]:
                return os.path.basename(files[0])
    return None


def _short_name(proxy):
    name = _registered_name(proxy)
    # A script's OpenDataFile names a reader "NIfTIImageReader3"; its file says more.
    if re.fullmatch(r"[A-Za-z]+[0-9]+", name) and _file_name(proxy):
        name = _file_name(proxy)
    for ending in _ENDINGS:
        if name.lower().endswith(ending):
            return name[:-len(ending)]
    return name


def exploration_name(sources):
    """"ch2 + aal + brodmann": the sources' names without their file endings."""
    return " + ".join(_short_name(s) for s in sources)


def _rename(proxy, name):
    """Registers `proxy` under `name` (made unique with " (2)", " (3)"... when taken), so
    the Pipeline Browser says what each piece of the exploration is."""
    simple = _simple()
    taken = {key[0] for key, value in simple.GetSources().items()
             if not _same_proxy(value, proxy)}
    unique, n = name, 1
    while unique in taken:
        n += 1
        unique = "%s (%d)" % (name, n)
    simple.RenameSource(unique, proxy)
    return unique


def _channel_count(source):
    """Channels of a volume: the components of its point arrays (one 65-component array of
    a diffusion file is 65 channels)."""
    info = source.GetDataInformation().DataInformation
    arrays = info.GetAttributeInformation(0)
    return sum(arrays.GetArrayInformation(i).GetNumberOfComponents()
               for i in range(arrays.GetNumberOfArrays()))


def _grid(source):
    info = source.GetDataInformation()
    return (tuple(info.GetExtent()), tuple(round(b, 6) for b in info.GetBounds()))


def _consumers(proxy):
    """Filters that take `proxy` as an input."""
    found = []
    for other in _simple().GetSources().values():
        inputs = getattr(other, "Input", None) if other.GetProperty("Input") else None
        if inputs is None:
            continue
        for item in inputs if isinstance(inputs, (list, tuple)) else [inputs]:
            if _same_proxy(item, proxy):
                found.append(other)
    return found


def _unused_readers_like(source, time):
    """Readers (sources without an input) that nothing consumes yet, on `source`'s grid,
    in the order they were created: the other channels opened with it (each read at
    `time`)."""
    grid = _grid(source)
    readers = []
    for (name, gid), proxy in sorted(_simple().GetSources().items(),
                                     key=lambda item: int(item[0][1])):
        if proxy.GetProperty("Input") is not None or _consumers(proxy):
            continue
        if proxy.SMProxy.GetXMLGroup() != "sources":
            continue
        try:
            proxy.UpdatePipeline(time)
            if proxy.GetDataInformation().GetDataSetTypeAsString() != "vtkImageData" or \
                    _grid(proxy) != grid or _channel_count(proxy) < 1:
                continue
        except Exception:  # noqa: BLE001 - not a volume: not a channel to merge
            continue
        readers.append(proxy)
    if not any(_same_proxy(r, source) for r in readers):
        readers.insert(0, source)
    return readers


class Exploration(dict):
    """What explore_multichannel made (a dict with attribute access): name, inputs,
    merged (MergeChannels or None), reduction, display, domain (ReducedDomain), glyph,
    volume_view, domain_view, viewpoint (the BestViewpoint result), widgets (count)."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name)


def _steps(sources, view, widgets, gather):
    """The exploration a step at a time: yields the text of the step about to run (the
    GUI shows it), fills and finally yields the Exploration."""
    simple = _simple()
    sources = [s for s in (sources or []) if s is not None]
    if not sources:
        raise ValueError("select the channel readers (e.g. ch2, aal and brodmann, Ctrl+click in "
                         "the Pipeline Browser) or one multichannel volume first")
    time = _view_time(view)  # a series: everything at the step on screen, read once
    for s in sources:
        s.UpdatePipeline(time)
        if s.GetDataInformation().GetDataSetTypeAsString() != "vtkImageData":
            raise ValueError("%s is no volume (image data): select the channel readers or one "
                             "multichannel volume" % _registered_name(s))
    if len(sources) == 1 and _channel_count(sources[0]) == 1 and gather:
        sources = _unused_readers_like(sources[0], time)
    if len(sources) == 1 and _channel_count(sources[0]) < 2:
        raise ValueError("%s has one channel: a multichannel exploration needs several. Open "
                         "the other channels (files on the same grid), select them all and "
                         "press Explore Multichannel again" % _registered_name(sources[0]))
    name = exploration_name(sources)
    result = Exploration(name=name, inputs=list(sources), merged=None)
    if view is None:
        view = simple.GetActiveViewOrCreate("RenderView")
    result["volume_view"] = view

    volume = sources[0]
    if len(sources) > 1:
        yield "Merging %d channels (%s)" % (len(sources), name)
        volume = _filter("MergeChannels")(Input=list(sources))
        _rename(volume, "Channels of %s" % name)
        volume.UpdatePipeline(time)
        result["merged"] = volume

    yield "Computing features and reducing them (DimensionReduction; progress below)"
    reduction = _filter("DimensionReduction")(Input=volume)
    _rename(reduction, "Exploration of %s" % name)
    # At the step on screen: a new filter updated without a time reduces the first step,
    # and the view then reduces its own step again (twice the work for a series).
    reduction.UpdatePipeline(time)
    result["reduction"] = reduction

    yield "Showing the volume as Gaussian TF Volume and seeding %d widgets" % widgets
    for s in list(sources) + ([volume] if volume is not sources[0] else []):
        simple.Hide(s, view)
    from .seeding import auto_widgets
    from .transfer_function import show_gaussian_tf

    display = show_gaussian_tf(reduction, view)
    auto_widgets(display, widgets, view)
    result["display"] = display
    result["widgets"] = len(display.GaussianWidgets) // 8

    yield "Opening the reduced domain beside the volume"
    from .dual_domain import show_dual_domain

    dual = show_dual_domain(display, view)
    _rename(dual.filter, "Reduced domain of %s" % name)
    _rename(dual.glyph, "Widget spheres of %s" % name)
    result.update(domain=dual.filter, glyph=dual.glyph, domain_view=dual.domain_view,
                  stop=dual.stop)

    yield "Turning the camera to the best view"
    from .viewpoint import apply_best_viewpoint

    best = apply_best_viewpoint(reduction, view, disambiguate=True)
    if best.filter is not None:
        _rename(best.filter, "Best viewpoint of %s" % name)
    result["viewpoint"] = best
    simple.SetActiveView(view)
    simple.SetActiveSource(reduction)
    simple.Render(view)
    yield result


def explore_multichannel(sources, view=None, widgets=4, gather=False):
    """A first exploration of a multichannel volume, every piece named after it and left in
    the pipeline:

    * `sources`: several volumes on one grid (one channel each, e.g. readers of ch2, aal
      and brodmann: merged with MergeChannels, "Channels of ch2 + aal + brodmann") or one
      multichannel volume. ``gather=True`` (the GUI's button): one single-channel reader
      alone is joined by every other reader on its grid that nothing uses yet.
    * DimensionReduction with its defaults computes the features and reduces them
      ("Exploration of ch2 + aal + brodmann").
    * It is shown in `view` (default: the active render view) as a Gaussian TF Volume with
      `widgets` widgets seeded at the reduced domain's clusters (auto_widgets); the inputs
      are hidden there.
    * Its reduced domain opens beside it (show_dual_domain: "Reduced domain of ...", the
      widgets as spheres "Widget spheres of ...", draggable in the GUI).
    * The camera turns to the best view of the widgets' opacity (apply_best_viewpoint,
      "Best viewpoint of ..."), and the reduction becomes the active source.

    Returns an Exploration (name, inputs, merged, reduction, display, domain, glyph,
    volume_view, domain_view, viewpoint, widgets). A bad selection (nothing, no volume, a
    lone channel) is a ValueError that says what to select."""
    result = None
    for item in _steps(sources, view, int(widgets), gather):
        result = item
    return result


def _reduction_of(target):
    """The DimensionReduction at or upstream of `target` (a source or a display)."""
    proxy = getattr(target, "Input", None) if target is not None and \
        getattr(target, "SMProxy", target).GetXMLGroup() == "representations" else target
    seen = 0
    while proxy is not None and seen < 64:
        if proxy.SMProxy.GetXMLName() == "DimensionReduction":
            return proxy
        inputs = proxy.Input if proxy.GetProperty("Input") is not None else None
        if isinstance(inputs, (list, tuple)):
            inputs = inputs[0] if inputs else None
        proxy = getattr(inputs, "SMProxy", None) and inputs
        seen += 1
    return None


def _enumeration_text(proxy, name):
    """The text of an enumeration property's value ("PCA", not 0 or "'PCA'")."""
    prop = proxy.SMProxy.GetProperty(name)
    value = prop.GetElement(0)
    domain = prop.GetDomain("enum")
    for i in range(domain.GetNumberOfEntries() if domain is not None else 0):
        if domain.GetEntryValue(i) == value:
            return domain.GetEntryText(i)
    return str(value)


def show_spectrum(target=None, view=None, fraction=0.4, leading=20):
    """The eigenvalue spectrum of a DimensionReduction (`target`, or the reduction
    upstream of it, e.g. the ReducedDomain or the Gaussian TF display; default: the active
    source) as a bar chart: X the component (1, 2, ...), Y the eigenvalue, the title the
    method and the variance the kept components retain. It opens below `view` (default:
    the active view), taking `fraction` of its cell, its X axis on the `leading` first
    components; returns (chart view, its display)."""
    simple = _simple()
    reduction = _reduction_of(target if target is not None else simple.GetActiveSource())
    if reduction is None:
        raise ValueError("Show Spectrum needs a DimensionReduction (or a filter or display "
                         "downstream of one) as the active source")
    if view is None:
        view = simple.GetActiveView()
    reduction.UpdatePipeline(_view_time(view))  # the spectrum of the time step on screen
    reduction.UpdatePropertyInformation()
    chart = simple.CreateView("XYBarChartView")
    layout = simple.GetLayout(view) if view is not None else None
    if layout is not None:
        cell = layout.GetViewLocation(view)
        first = layout.SplitVertical(cell, 1.0 - float(fraction))
        layout.AssignView(first + 1, chart)
    else:
        simple.AssignViewToLayout(view=chart)
    bars = simple.Show(simple.OutputPort(reduction, 1), chart)
    bars.UseIndexForXAxis = 0
    bars.XArrayName = "index"
    bars.SeriesVisibility = ["value"]
    bars.SeriesLabel = ["value", "eigenvalue"]
    bars.SeriesColor = ["value", "0.89", "0.10", "0.11"]
    method = _enumeration_text(reduction, "Method")
    dims = int(reduction.SMProxy.GetProperty("OutputDimension").GetElement(0))
    variance = [float(v) for v in reduction.GetProperty("VarianceRetained")] \
        if reduction.GetProperty("VarianceRetained") is not None else []
    title = "%s spectrum: %d components kept" % (method, dims)
    if variance and method not in ("LLE", "UMAP") and 0 <= variance[0] <= 1:
        title += ", %.0f%% of the variance" % (100 * variance[0])
    chart.ChartTitle = title
    chart.BottomAxisTitle = "Component"
    chart.LeftAxisTitle = "Eigenvalue" if method in ("LLE", "UMAP") else "Eigenvalue (variance)"
    chart.ShowLegend = 0
    # The leading components: a 65-channel volume has 130 or 520 eigenvalues, whose bars
    # would be hairlines; the others stay in the table (and a zoom away).
    count = len([float(v) for v in reduction.GetProperty("EigenvalueSpectrum")]) \
        if reduction.GetProperty("EigenvalueSpectrum") is not None else 0
    shown = min(count, int(leading)) if count else int(leading)
    chart.BottomAxisUseCustomRange = 1
    chart.BottomAxisRangeMinimum = 0.5
    chart.BottomAxisRangeMaximum = shown + 0.5
    chart.ChartTitleFontSize = 14
    chart.LeftAxisTitleFontSize = 12
    chart.BottomAxisTitleFontSize = 12
    simple.Render(chart)
    return chart, bars


# ---- the GUI's button: the same steps, one per call, with their text for the status bar.
text = ""       # what runs now, the final message, or the error
done = False    # the last _gui_step finished the exploration (or failed)
failed = False
last = None     # the last Exploration the button made
_pending = None


def _gui_begin(global_ids, widgets=4):
    """Starts the exploration of the sources with these global ids (the GUI's selection);
    ``text`` holds the first step's description."""
    global _pending, text, done, failed
    from paraview import servermanager

    session = servermanager.ActiveConnection.Session
    sources = []
    for gid in global_ids:
        proxy = session.GetRemoteObject(int(gid))
        if proxy is not None:
            sources.append(servermanager._getPyProxy(proxy))
    _pending = _steps(sources, _simple().GetActiveView(), int(widgets), True)
    done = failed = False
    _gui_step()


def _gui_step():
    """Runs the next step; ``text`` says what runs next, or, with ``done``, the result."""
    global _pending, text, done, failed, last
    try:
        item = next(_pending)
    except StopIteration:
        item = None
    except Exception as error:  # noqa: BLE001 - shown to the user in a message box
        text = "Explore Multichannel: %s" % error
        if not isinstance(error, ValueError):
            _warn(text)
        done = failed = True
        _pending = None
        return text
    if isinstance(item, Exploration):
        last = item
        done, _pending = True, None
        text = ("Explored %s: %d Gaussian widgets seeded. Drag a sphere in the reduced "
                "domain (right) or edit the widgets in the Gaussian Widgets panel; Probe "
                "reads a voxel; Edit > Undo Explore Multichannel removes it all."
                % (item.name, item.widgets))
    elif item is None:
        done, _pending = True, None
    else:
        text = "Explore Multichannel: %s..." % item
    return text


def _show_domain():
    """Show Reduced Domain on the active source's Gaussian TF Volume display; returns
    what the status bar says."""
    simple = _simple()
    from paraview import servermanager

    from ._common import _find_filter
    from .dual_domain import show_dual_domain
    from .transfer_function import _gaussian_tf_display

    view = simple.GetActiveView()
    source = simple.GetActiveSource()
    display = _gaussian_tf_display(source, view)
    if display is None:
        raise ValueError("select a volume shown as Gaussian TF Volume in the active view "
                         "(pick Gaussian TF Volume in the Representation box, or press "
                         "Explore Multichannel)")
    domain = _find_filter(source, "ReducedDomain")
    for other in simple.GetViews() if domain is not None else []:
        rep = servermanager.GetRepresentation(domain, other)
        if rep is not None and rep.Visibility:
            return ("The reduced domain of %s is already shown (%s): drag its spheres "
                    "there" % (_registered_name(source), _registered_name(domain)))
    if not len(display.GaussianWidgets):
        from .seeding import auto_widgets

        auto_widgets(display, 4, view)
    dual = show_dual_domain(display, view)
    name = _registered_name(source)
    _rename(dual.filter, "Reduced domain of %s" % name)
    _rename(dual.glyph, "Widget spheres of %s" % name)
    simple.SetActiveView(view)
    simple.SetActiveSource(source)
    return ("Reduced domain of %s opened on the right: drag a sphere to move its widget, "
            "shift+drag to resize it" % name)


def _gui_show_domain():
    """What the Show Reduced Domain button runs: ``text`` is what the status bar (or, on
    an error, a message box) shows."""
    global text
    text = _gui_text("Show Reduced Domain", _show_domain)
    return text


def _gui_show_spectrum():
    """What the Show Spectrum button runs: ``text`` as for _gui_show_domain."""
    global text
    text = _gui_text("Show Spectrum", lambda: "Spectrum: %s" % show_spectrum()[0].ChartTitle)
    return text
