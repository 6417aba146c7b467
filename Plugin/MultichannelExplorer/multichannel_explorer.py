"""Python helpers of the MultichannelExplorer ParaView plugin.

Shipped inside the plugin (PYTHON_MODULES): importable in pvpython, pvbatch and the GUI's
Python shell once the plugin is loaded::

    from paraview.simple import *
    LoadPlugin("/path/to/MultichannelExplorer.so", remote=False, ns=globals())
    import multichannel_explorer as mce

    volume = OpenDataFile("ch2.nii.gz")
    view = GetActiveViewOrCreate("RenderView")
    Show(volume, view).SetRepresentationType("Volume")
    result = mce.apply_best_viewpoint(volume, view)            # camera along v3
    print(result.direction, result.eigenvalues)
    mce.apply_best_viewpoint(volume, view, which="worst")       # camera along v1
    mce.apply_best_viewpoint(volume, view, disambiguate=True)   # +v3 or -v3, by entropy

The "Best Viewpoint" toolbar button of the GUI runs
``apply_best_viewpoint(GetActiveSource(), GetActiveView(), disambiguate=True)``.

Nothing here imports paraview.simple at module level, so importing the module is cheap
and safe in any ParaView process.
"""

import math
import os
import tempfile

__all__ = [
    "ViewpointResult",
    "best_viewpoint_filter",
    "apply_best_viewpoint",
    "set_camera_direction",
    "image_entropy",
    "image_statistics",
    "reduce_multichannel",
    "reduced_domain_filter",
    "auto_widgets",
    "show_dual_domain",
    "follow_best_viewpoint",
    "stop_following",
    "turn_camera",
    "GAUSSIAN_TF_REPRESENTATION",
    "show_gaussian_tf",
]

_FILTER_XML_NAME = "BestViewpoint"


class ViewpointResult(dict):
    """What apply_best_viewpoint did: a dict whose keys are also attributes.

    Keys: ``direction`` (unit vector the camera looks along), ``which``, ``best``,
    ``worst``, ``view_up``, ``eigenvalues`` (descending, sum 1), ``center`` (focal
    point), ``valid``, ``device``, ``filter`` (the BestViewpoint proxy), ``entropies``
    ({"+": bits, "-": bits} when disambiguate=True, else None), ``sign`` (+1 or -1
    relative to the filter's direction), ``camera_position``.
    """

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name)


def _simple():
    from paraview import simple

    return simple


def _warn(message):
    """Warnings go where ParaView shows them (Output Messages in the GUI, stderr in
    pvpython/pvbatch)."""
    try:
        from vtkmodules.vtkCommonCore import vtkOutputWindow

        vtkOutputWindow.GetInstance().DisplayWarningText(
            "multichannel_explorer: %s\n" % message)
    except Exception:  # pragma: no cover - last resort
        import sys

        sys.stderr.write("multichannel_explorer: warning: %s\n" % message)


def _same_proxy(a, b):
    if a is None or b is None:
        return False
    a = getattr(a, "SMProxy", a)
    b = getattr(b, "SMProxy", b)
    return a is b or (hasattr(a, "GetGlobalID") and hasattr(b, "GetGlobalID")
                      and a.GetGlobalID() == b.GetGlobalID())


def _find_filter(source, xml_name=_FILTER_XML_NAME):
    """The filter of type `xml_name` (default BestViewpoint) already applied to `source`,
    or None."""
    simple = _simple()
    for proxy in simple.GetSources().values():
        if proxy.SMProxy.GetXMLName() != xml_name:
            continue
        inputs = proxy.Input
        if not isinstance(inputs, (list, tuple)):
            inputs = [inputs]
        for inp in inputs:
            if _same_proxy(inp, source):
                return proxy
    return None


def _volume_display(source, view):
    """The source's representation in `view` when it is visible as a Volume, else None."""
    if view is None:
        return None
    from paraview import servermanager

    rep = servermanager.GetRepresentation(source, view)
    if rep is None:
        return None
    try:
        if not rep.Visibility or rep.Representation != "Volume":
            return None
    except AttributeError:
        return None
    return rep


GAUSSIAN_TF_REPRESENTATION = "Gaussian TF Volume"


def _gaussian_tf_display(source, view):
    """The source's representation in `view` when it is visible as a Gaussian TF Volume."""
    if view is None or source is None:
        return None
    from paraview import servermanager

    rep = servermanager.GetRepresentation(source, view)
    try:
        if rep is None or not rep.Visibility or \
                rep.Representation != GAUSSIAN_TF_REPRESENTATION:
            return None
    except AttributeError:
        return None
    return rep


def _widget_values(display):
    return [float(v) for v in display.GetProperty("GaussianWidgets")]


def _coordinates_name(display):
    """Name of the coordinate array a Gaussian TF display maps through its widgets."""
    prop = display.SMProxy.GetProperty("CoordinateArray")
    if prop is not None and prop.GetNumberOfElements() > 0:
        # An array selection (association, name) or a plain name: the name is last.
        name = prop.GetElement(prop.GetNumberOfElements() - 1)
        if name:
            return str(name)
    return "ReducedCoordinates"


def best_viewpoint_filter(source, view=None, **filter_properties):
    """Creates (or reuses) the BestViewpoint filter on `source`, sets its properties,
    updates it and its information properties, and returns it.

    When `source` is shown as a Volume in `view` and neither OpacityFunction nor
    Channels is given, the filter follows that display: its Scalar Opacity Function and
    its colouring array. When it is shown as a "Gaussian TF Volume", the filter takes
    the opacity of that display's Gaussian widgets (OpacitySource = Representation).
    The active source is left as it was.
    """
    if source is None:
        raise ValueError("best_viewpoint_filter: no source given")
    simple = _simple()
    active = simple.GetActiveSource()
    bvp = _find_filter(source)
    if bvp is None:
        ctor = getattr(simple, _FILTER_XML_NAME, None)
        if ctor is None:
            simple._add_functions(vars(simple))
            ctor = getattr(simple, _FILTER_XML_NAME, None)
        if ctor is None:
            raise RuntimeError(
                "The BestViewpoint filter is not available: load the MultichannelExplorer "
                "plugin first, e.g. LoadPlugin(path, remote=False, ns=globals())")
        bvp = ctor(Input=source)
        if active is not None:
            simple.SetActiveSource(active)

    rep = _volume_display(source, view)
    gaussian = _gaussian_tf_display(source, view)
    if gaussian is not None and "OpacitySource" not in filter_properties:
        # The best view of what the multichannel transfer function shows.
        filter_properties["OpacitySource"] = "Representation"
        filter_properties.setdefault("GaussianWidgets", _widget_values(gaussian))
        filter_properties.setdefault("WidgetCoordinates", _coordinates_name(gaussian))
    if rep is not None:
        if "OpacityFunction" not in filter_properties:
            filter_properties["OpacityFunction"] = rep.ScalarOpacityFunction
        if "Channels" not in filter_properties:
            try:
                association, name = rep.ColorArrayName[0], rep.ColorArrayName[1]
            except (IndexError, TypeError):
                association, name = None, None
            if name and association == "POINTS":
                filter_properties["Channels"] = [name]
    for key, value in filter_properties.items():
        if key == "OpacityFunction" and value is None:
            bvp.GetProperty("OpacityFunction").SetData(None)
            continue
        setattr(bvp, key, value)
    bvp.UpdatePipeline()
    bvp.UpdatePropertyInformation()
    return bvp


def _vec(proxy, name):
    return [float(x) for x in proxy.GetPropertyValue(name)]


def set_camera_direction(view, center, direction, view_up, fill=True):
    """Points the camera of `view` along `direction` (from the camera towards `center`),
    with `view_up`, keeping the current distance; then resets the camera so the visible
    data fills the view (the direction is kept)."""
    simple = _simple()
    focal = [float(c) for c in center]
    pos = [float(p) for p in view.CameraPosition]
    old_focal = [float(p) for p in view.CameraFocalPoint]
    distance = math.sqrt(sum((p - f) ** 2 for p, f in zip(pos, old_focal)))
    if not distance > 1e-9:
        distance = 1.0
    view.CameraFocalPoint = focal
    view.CameraPosition = [f - d * distance for f, d in zip(focal, direction)]
    view.CameraViewUp = [float(u) for u in view_up]
    if fill:
        try:
            view.ResetCamera(True)  # closest fit, direction kept
        except TypeError:
            view.ResetCamera()
        # Reset moves the focal point to the centre of the visible bounds; keep ours
        # (the volume's centre) at the same distance.
        pos = [float(p) for p in view.CameraPosition]
        f2 = [float(p) for p in view.CameraFocalPoint]
        distance = math.sqrt(sum((p - f) ** 2 for p, f in zip(pos, f2)))
        view.CameraFocalPoint = focal
        view.CameraPosition = [f - d * distance for f, d in zip(focal, direction)]
        view.CameraViewUp = [float(u) for u in view_up]
    simple.Render(view)


def _read_png(path):
    from vtkmodules.vtkIOImage import vtkPNGReader

    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def _luminance_histogram(image):
    """256-bin histogram of the 8-bit luminance of a vtkImageData (RGB, RGBA or grey).
    Pure VTK + Python (ParaView's Python has neither numpy nor vtkImagingStatistics)."""
    from vtkmodules.vtkCommonCore import VTK_UNSIGNED_CHAR
    from vtkmodules.vtkImagingColor import vtkImageLuminance
    from vtkmodules.vtkImagingCore import vtkImageCast, vtkImageExtractComponents

    source = image
    scalars = image.GetPointData().GetScalars()
    if scalars is None:
        raise ValueError("image has no scalars")
    ncomp = scalars.GetNumberOfComponents()
    if ncomp != 1:
        extract = vtkImageExtractComponents()
        extract.SetInputData(image)
        if ncomp >= 3:
            extract.SetComponents(0, 1, 2)
            lum = vtkImageLuminance()
            lum.SetInputConnection(extract.GetOutputPort())
            lum.Update()
            source = lum.GetOutput()
        else:
            extract.SetComponents(0)
            extract.Update()
            source = extract.GetOutput()
    if source.GetPointData().GetScalars().GetDataType() != VTK_UNSIGNED_CHAR:
        cast = vtkImageCast()
        cast.SetInputData(source)
        cast.SetOutputScalarTypeToUnsignedChar()
        cast.ClampOverflowOn()
        cast.Update()
        source = cast.GetOutput()
    data = bytes(memoryview(source.GetPointData().GetScalars()))
    return [data.count(bytes((i,))) for i in range(256)]


def _entropy(counts):
    total = float(sum(counts))
    if total <= 0:
        return 0.0
    return -sum((c / total) * math.log2(c / total) for c in counts if c > 0)


def image_entropy(image_or_path):
    """Shannon entropy (bits) of the 8-bit luminance histogram of an image (a PNG path
    or a vtkImageData)."""
    image = _read_png(image_or_path) if isinstance(image_or_path, str) else image_or_path
    return _entropy(_luminance_histogram(image))


def image_statistics(image_or_path):
    """{'mean', 'stddev', 'entropy', 'non_background_fraction', 'pixels'} of an image's
    8-bit luminance (non-background: pixels that differ from the most common value)."""
    image = _read_png(image_or_path) if isinstance(image_or_path, str) else image_or_path
    counts = _luminance_histogram(image)
    total = float(sum(counts)) or 1.0
    mean = sum(i * c for i, c in enumerate(counts)) / total
    var = sum(c * (i - mean) ** 2 for i, c in enumerate(counts)) / total
    return {
        "mean": mean,
        "stddev": math.sqrt(var),
        "entropy": _entropy(counts),
        "non_background_fraction": 1.0 - max(counts) / total,
        "pixels": int(total),
    }


def _render_entropy(view, resolution=None):
    simple = _simple()
    fd, path = tempfile.mkstemp(prefix="mcv_view_", suffix=".png")
    os.close(fd)
    try:
        params = {}
        if resolution:
            params["ImageResolution"] = list(resolution)
        simple.SaveScreenshot(path, view, **params)
        return image_entropy(path)
    finally:
        try:
            os.remove(path)
        except OSError:
            pass


def apply_best_viewpoint(source, view=None, which="best", disambiguate=False,
                         **filter_properties):
    """Turns the camera of `view` (default: the active view) to the best (or worst) view
    of `source`, a volume (image data).

    * Creates or updates a BestViewpoint filter on `source` with `filter_properties`
      (e.g. NumberOfInterestPoints=1024, Channels=["a", "b"], Method="AreaMaximizing").
      When `source` is shown as a Volume in `view`, the filter uses that display's
      Scalar Opacity Function (and colouring array) unless they are given.
    * which="best": the camera looks along v3 (least variance of the interest points);
      which="worst": along v1. View-up is v2 in both cases.
    * The focal point is the volume's centre; the camera is then reset (direction kept)
      so the data fills the view, and the view is rendered.
    * disambiguate=True: v and -v are equally good by variance; both are rendered and
      the one whose image has the higher luminance entropy is kept.

    Returns a ViewpointResult (dict with attribute access). When no direction could be
    found (flat or constant volume), a warning is given, the camera is left as it was
    and result.valid is False.
    """
    simple = _simple()
    if which not in ("best", "worst"):
        raise ValueError('which must be "best" or "worst", not %r' % (which,))
    if source is None:
        raise ValueError("apply_best_viewpoint: no source given")
    if view is None:
        view = simple.GetActiveViewOrCreate("RenderView")
    if not hasattr(view, "CameraPosition"):
        raise ValueError("apply_best_viewpoint needs a render view, not %s"
                         % view.GetXMLName())

    bvp = best_viewpoint_filter(source, view, **filter_properties)
    best = _vec(bvp, "BestViewDirection")
    worst = _vec(bvp, "WorstViewDirection")
    up = _vec(bvp, "ViewUp")
    eig = _vec(bvp, "EigenvalueSpectrum")
    center = _vec(bvp, "DataCenter")
    valid = bool(bvp.GetPropertyValue("ViewValid"))
    device = bvp.GetPropertyValue("DeviceUsed")
    direction = best if which == "best" else worst
    result = ViewpointResult(
        direction=direction, which=which, best=best, worst=worst, view_up=up,
        eigenvalues=eig, center=center, valid=valid, device=device, filter=bvp,
        entropies=None, sign=1, camera_position=None)
    if not valid or sum(d * d for d in direction) < 0.5:
        _warn("no %s view direction for this volume (flat or constant opacity?): "
              "the camera was not changed" % which)
        result["valid"] = False
        return result

    sign = 1
    if disambiguate:
        entropies = {}
        for s, key in ((1, "+"), (-1, "-")):
            set_camera_direction(view, center, [s * d for d in direction], up)
            entropies[key] = _render_entropy(view)
        result["entropies"] = entropies
        sign = 1 if entropies["+"] >= entropies["-"] else -1
    final = [sign * d for d in direction]
    set_camera_direction(view, center, final, up)
    result["direction"] = final
    result["sign"] = sign
    result["camera_position"] = [float(p) for p in view.CameraPosition]
    return result


def reduce_multichannel(source, method="Isomap", features="24D", output_dimension=3,
                        **props):
    """Feature vectors of a multichannel volume reduced to a 2D/3D domain.

    Builds ``MultichannelFeatures(Input=source, FeatureSet=features)`` followed by
    ``DimensionReduction(Method=method, OutputDimension=output_dimension, **props)`` and
    returns ``(features_proxy, reduction_proxy)``. ``features`` is a preset of
    MultichannelFeatures ("6D", "24D") or the name of a point array of `source` that
    already holds feature vectors (then no MultichannelFeatures filter is made and the
    first proxy returned is `source`). ``props`` are further DimensionReduction
    properties (NumberOfNeighbors, NumberOfLandmarks, ReferenceSampleSize, RandomSeed,
    Device). Nothing is shown or updated; the reduced coordinates are the point array
    ReducedCoordinates of the reduction's first output, its spectrum the second output::

        feats, red = mce.reduce_multichannel(volume, "PCA", "6D", ReferenceSampleSize=5000)
        red.UpdatePipeline(); red.UpdatePropertyInformation()
        print(red.VarianceRetained, red.Trustworthiness)
    """
    simple = _simple()
    if not hasattr(simple, "DimensionReduction"):
        raise RuntimeError("DimensionReduction is not available: load the "
                           "MultichannelExplorer plugin first")
    if features in ("6D", "24D", "Custom"):
        if not hasattr(simple, "MultichannelFeatures"):
            raise RuntimeError("MultichannelFeatures is not available in this plugin build")
        feats = simple.MultichannelFeatures(Input=source)
        feats.FeatureSet = features
        array = "Features"
    else:
        feats = source
        array = str(features)
    reduction = simple.DimensionReduction(Input=feats)
    reduction.Features = ["POINTS", array]
    reduction.Method = method
    reduction.OutputDimension = int(output_dimension)
    for name, value in props.items():
        setattr(reduction, name, value)
    return feats, reduction


# ---- The multichannel transfer function: reduced domain, widgets, following views ------

def _is_representation(proxy):
    proxy = getattr(proxy, "SMProxy", proxy)
    return proxy is not None and proxy.GetXMLGroup() == "representations"


def _source_and_display(target, view=None):
    """(source, Gaussian TF display or None) for a source or a representation proxy."""
    if target is None:
        raise ValueError("no source or display given")
    if _is_representation(target):
        return target.Input, target
    if view is None:
        view = _simple().GetActiveView()
    return target, _gaussian_tf_display(target, view)


def reduced_domain_filter(source, **props):
    """Creates (or reuses) the ReducedDomain filter on `source` (a volume with
    ReducedCoordinates), sets `props` (SampleSize, RandomSeed, GaussianWidgets,
    SeedWidgetCount, Coordinates, ...) and returns it, not shown and not updated. The
    active source is left as it was."""
    simple = _simple()
    if not hasattr(simple, "ReducedDomain"):
        raise RuntimeError("ReducedDomain is not available: load the MultichannelExplorer "
                           "plugin first")
    domain = _find_filter(source, "ReducedDomain")
    if domain is None:
        active = simple.GetActiveSource()
        domain = simple.ReducedDomain(Input=source)
        if active is not None:
            simple.SetActiveSource(active)
    for name, value in props.items():
        setattr(domain, name, value)
    return domain


def auto_widgets(target, count=4, view=None, opacity=0.5, seed=0, sample_size=20000,
                 skip_background=True):
    """Seeds `count` Gaussian widgets at the k-means cluster centres of the reduced domain
    (largest cluster first, distinct hues, sigma = each cluster's spread, peak `opacity`).
    With `skip_background` (default) count + 1 clusters are made and the largest, almost
    always the volume's background, gets no widget.

    `target` is a volume with ReducedCoordinates or its "Gaussian TF Volume" display; when
    a display is given (or the volume is shown as one in `view`), its GaussianWidgets are
    set. Returns the flat widget list (8 numbers per widget: cx, cy, cz, sigma, r, g, b,
    opacity)::

        display = mce.show_gaussian_tf(reduction, view)
        mce.auto_widgets(display, 3)
    """
    if int(count) < 1:
        raise ValueError("auto_widgets needs count >= 1, not %r" % (count,))
    source, display = _source_and_display(target, view)
    props = dict(SeedWidgetCount=int(count), SeedWidgetOpacity=float(opacity),
                 RandomSeed=int(seed), SampleSize=int(sample_size),
                 SkipLargestCluster=1 if skip_background else 0)
    if display is not None:
        props["Coordinates"] = ["POINTS", _coordinates_name(display)]
    domain = reduced_domain_filter(source, **props)
    domain.UpdatePipeline()
    domain.UpdatePropertyInformation()
    widgets = [float(v) for v in domain.GetProperty("SeededWidgets")]
    domain.SeedWidgetCount = 0  # one suggestion; later updates only recolour
    if not widgets:
        raise RuntimeError("auto_widgets: no widgets could be seeded (see the messages of "
                           "ReducedDomain)")
    if display is not None:
        display.GaussianWidgets = widgets
    return widgets


class _Follower(object):
    """Calls `callback` whenever a proxy property changes; stop() ends it."""

    def __init__(self, proxy, prop_name, callback):
        self.property = proxy.GetProperty(prop_name)
        if self.property is None:
            raise ValueError("%s has no property %s" % (proxy.GetXMLName(), prop_name))
        self.property = getattr(self.property, "SMProperty", self.property)
        self.callback = callback
        self.tag = self.property.AddObserver("ModifiedEvent", self._fire)
        self.busy = False

    def _fire(self, *unused):
        if self.busy:  # a change made by the callback itself
            return
        self.busy = True
        try:
            self.callback()
        finally:
            self.busy = False

    def stop(self):
        if self.tag is not None:
            self.property.RemoveObserver(self.tag)
            self.tag = None


def show_dual_domain(target, volume_view=None, sample_size=20000, point_size=3,
                     widget_opacity=0.35):
    """Shows the reduced domain beside the volume: splits the volume view's layout cell
    and puts a render view with the domain's point cloud (a sample of `sample_size`
    voxels at their reduced coordinates, coloured by the widgets over grey) and the
    widgets as translucent spheres (diameter 2 sigma, the widget's colour).

    `target`: a "Gaussian TF Volume" display, or the volume shown as one in
    `volume_view`. While the returned object lives, every change of the display's
    GaussianWidgets recolours the domain (call .stop() to end that). Returns a
    ViewpointResult-like dict: filter, domain_view, volume_view, domain_display,
    widget_display, stop."""
    simple = _simple()
    if volume_view is None:
        volume_view = simple.GetActiveViewOrCreate("RenderView")
    source, display = _source_and_display(target, volume_view)
    props = dict(SampleSize=int(sample_size))
    if display is not None:
        props["GaussianWidgets"] = _widget_values(display)
        props["Coordinates"] = ["POINTS", _coordinates_name(display)]
    domain = reduced_domain_filter(source, **props)

    domain_view = simple.CreateView("RenderView")
    layout = simple.GetLayout(volume_view)
    if layout is None:  # pvbatch: views are in no layout until given one
        layout = simple.CreateLayout("Multichannel transfer function")
        simple.AssignViewToLayout(view=volume_view, layout=layout, hint=0)
    cell = layout.GetViewLocation(volume_view)
    first = layout.SplitHorizontal(cell, 0.5)
    layout.AssignView(first + 1, domain_view)
    points = simple.Show(simple.OutputPort(domain, 0), domain_view)
    points.SetRepresentationType("Points")
    simple.ColorBy(points, ("POINTS", "DisplayColor"))
    points.MapScalars = 0  # the colours themselves, not a colour map
    points.PointSize = point_size
    glyph = simple.Glyph(Input=simple.OutputPort(domain, 1), GlyphType="Sphere")
    glyph.ScaleArray = ["POINTS", "Diameter"]
    glyph.ScaleFactor = 1.0
    glyph.GlyphMode = "All Points"
    spheres = simple.Show(glyph, domain_view)
    simple.ColorBy(spheres, ("POINTS", "Color"))
    spheres.MapScalars = 0
    spheres.Opacity = widget_opacity
    simple.ResetCamera(domain_view)
    simple.Render(domain_view)

    follower = None
    if display is not None:
        def recolour():
            domain.GaussianWidgets = _widget_values(display)
            simple.Render(domain_view)
        follower = _Follower(display, "GaussianWidgets", recolour)
    _followers.append(follower)
    return ViewpointResult(filter=domain, glyph=glyph, domain_view=domain_view, layout=layout,
                           volume_view=volume_view, domain_display=points,
                           widget_display=spheres,
                           stop=(follower.stop if follower else (lambda: None)))


_followers = []  # keeps observers' Python callbacks alive


def _normalized(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v] if n > 0 else list(v)


def _slerp(a, b, t):
    """Unit vector a fraction t of the way from unit vector a to b along the great circle."""
    dot = max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b))))
    angle = math.acos(dot)
    if angle < 1e-6:
        return list(b)
    if math.pi - angle < 1e-6:  # opposite: turn through any perpendicular
        perp = _normalized([a[1], -a[0], 0.0] if abs(a[2]) < 0.9 else [0.0, a[2], -a[1]])
        return _normalized([math.cos(t * math.pi) * x + math.sin(t * math.pi) * y
                            for x, y in zip(a, perp)])
    s = math.sin(angle)
    return [(math.sin((1 - t) * angle) * x + math.sin(t * angle) * y) / s
            for x, y in zip(a, b)]


def turn_camera(view, center, direction, view_up, frames=10):
    """Turns the camera of `view` to look along `direction` at `center` in `frames`
    rendered steps (great-circle interpolation of the direction and the view-up), then
    fits the data in the view. frames <= 1: at once."""
    position = [float(p) for p in view.CameraPosition]
    focal = [float(p) for p in view.CameraFocalPoint]
    start = _normalized([f - p for f, p in zip(focal, position)])
    start_up = _normalized([float(u) for u in view.CameraViewUp])
    goal, goal_up = _normalized(direction), _normalized(view_up)
    for i in range(1, max(1, int(frames))):
        t = float(i) / frames
        d = _slerp(start, goal, t)
        up = _slerp(start_up, goal_up, t)
        # Keep view-up perpendicular to the direction.
        dot = sum(x * y for x, y in zip(up, d))
        up = _normalized([u - dot * x for u, x in zip(up, d)])
        set_camera_direction(view, center, d, up, fill=False)
    set_camera_direction(view, center, goal, goal_up)


def follow_best_viewpoint(display, view=None, frames=10, which="best", **filter_properties):
    """Keeps the camera of `view` on the best view of what a "Gaussian TF Volume"
    `display` shows: now, and after every change of its GaussianWidgets the best
    viewpoint is recomputed from the widgets' opacity and the camera turns there in
    `frames` rendered steps. Returns an object with .stop() (also stop_following())."""
    simple = _simple()
    if view is None:
        view = simple.GetActiveView()
    if not _is_representation(display):
        source = display
        display = _gaussian_tf_display(source, view)
        if display is None:
            raise ValueError("follow_best_viewpoint needs a display of type %r in the view"
                             % GAUSSIAN_TF_REPRESENTATION)
    source = display.Input
    state = {"result": None}

    def update():
        props = dict(filter_properties)
        props.update(OpacitySource="Representation", GaussianWidgets=_widget_values(display),
                     WidgetCoordinates=_coordinates_name(display))
        bvp = best_viewpoint_filter(source, view, **props)
        direction = _vec(bvp, "BestViewDirection" if which == "best" else "WorstViewDirection")
        if not bvp.GetPropertyValue("ViewValid") or sum(d * d for d in direction) < 0.5:
            _warn("follow_best_viewpoint: no %s view for these widgets; the camera stays"
                  % which)
            return
        # Of +v and -v, the one nearer the current camera: the smallest turn.
        position = [float(p) for p in view.CameraPosition]
        focal = [float(p) for p in view.CameraFocalPoint]
        current = [f - p for f, p in zip(focal, position)]
        if sum(c * d for c, d in zip(current, direction)) < 0:
            direction = [-d for d in direction]
        turn_camera(view, _vec(bvp, "DataCenter"), direction, _vec(bvp, "ViewUp"), frames)
        state["result"] = ViewpointResult(direction=direction, filter=bvp, which=which,
                                          eigenvalues=_vec(bvp, "EigenvalueSpectrum"))

    follower = _Follower(display, "GaussianWidgets", update)
    _followers.append(follower)
    update()
    follower.state = state
    return follower


def stop_following():
    """Ends every follow_best_viewpoint / show_dual_domain observer."""
    while _followers:
        follower = _followers.pop()
        if follower is not None:
            follower.stop()


def _flat_widgets(widgets):
    """A flat list of floats from a flat list or from 8-value widgets."""
    flat = []
    for item in widgets or ():
        if isinstance(item, (list, tuple)):
            flat.extend(float(v) for v in item)
        else:
            flat.append(float(item))
    return flat


def show_gaussian_tf(source, view=None, widgets=(), coordinates="ReducedCoordinates",
                     blend="Composite"):
    """Shows `source` (image data with a 2- or 3-component point array of reduced
    coordinates, e.g. the output of DimensionReduction) as a "Gaussian TF Volume" in
    `view` (default: the active render view) and returns the display.

    ``widgets``: a flat list of 8 numbers per widget (cx, cy, cz, sigma, r, g, b,
    opacity) or a sequence of such 8-tuples; ``coordinates``: the point array of reduced
    coordinates; ``blend``: "Composite" or "Maximum Intensity". Edit the widgets later
    with ``display.GaussianWidgets = [...]`` and ``Render()``: only the colours are
    recomputed, the volume is not delivered again::

        display = mce.show_gaussian_tf(reduction, view,
                                       widgets=[(0.2, 0.1, 0, 0.05, 1, 0, 0, 1),
                                                (0.7, 0.4, 0, 0.05, 0, 1, 0, 1)],
                                       blend="Maximum Intensity")
    """
    simple = _simple()
    if view is None:
        view = simple.GetActiveViewOrCreate("RenderView")
    display = simple.Show(source, view)
    if GAUSSIAN_TF_REPRESENTATION not in display.GetProperty("Representation").Available:
        raise RuntimeError('"%s" is not a representation of this source (image data '
                           "only; is the MultichannelExplorer plugin loaded?)"
                           % GAUSSIAN_TF_REPRESENTATION)
    display.SetRepresentationType(GAUSSIAN_TF_REPRESENTATION)
    display.CoordinateArray = str(coordinates)
    display.GaussianBlendMode = str(blend)
    display.GaussianWidgets = _flat_widgets(widgets)
    return display
