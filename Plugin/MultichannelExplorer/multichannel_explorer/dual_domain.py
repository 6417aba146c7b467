"""The dual domain: the ReducedDomain filter on a volume of reduced coordinates, and the
reduced domain (a point cloud and the widgets as spheres) shown beside the volume,
recoloured whenever the widgets change.
"""

from ._common import _Follower, _TracedProperties, _filter, _find_filter, _followers, _simple
from .transfer_function import _coordinates_name, _source_and_display, _widget_values
from .viewpoint import ViewpointResult

__all__ = [
    "reduced_domain_filter",
    "show_dual_domain",
]


def reduced_domain_filter(source, **props):
    """Creates (or reuses) the ReducedDomain filter on `source` (a volume with
    ReducedCoordinates), sets `props` (SampleSize, RandomSeed, GaussianWidgets,
    SeedWidgetCount, Coordinates, ...) and returns it, not shown and not updated. The
    active source is left as it was."""
    simple = _simple()
    domain = _find_filter(source, "ReducedDomain")
    if domain is None:
        active = simple.GetActiveSource()
        domain = _filter("ReducedDomain")(Input=source)
        if active is not None:
            simple.SetActiveSource(active)
    with _TracedProperties(domain):  # recorded in a trace being recorded
        for name, value in props.items():
            setattr(domain, name, value)
    return domain


def _same_background(source_view, view):
    """`view` gets `source_view`'s background (its own colours, or the palette's), so the
    two halves of the dual domain look like one figure."""
    for name in ("UseColorPaletteForBackground", "BackgroundColorMode", "Background",
                 "Background2"):
        have = source_view.GetProperty(name)
        if have is not None and view.GetProperty(name) is not None:
            view.SetPropertyWithName(name, have.GetData())


def _frame_focus(domain, view):
    """Frames `view` on the domain's FocusBounds (the sampled points without those cut off
    from the rest by an empty gap, and the shown widgets' spheres): a few far outlying
    points would otherwise shrink the dense cloud to a corner. ParaView's Reset Camera still
    shows every point.
    Returns the bounds used, or None (no FocusBounds: the view is left as it is)."""
    info = domain.GetDataInformation(0).GetFieldDataInformation().GetArrayInformation(
        "FocusBounds")
    if info is None or info.GetNumberOfComponents() != 6:
        return None
    # one tuple (piece 0's; the other pieces have none): each component's range is its value
    bounds = [info.GetComponentRange(c)[0] for c in range(6)]
    view.ResetCamera(*bounds)
    return bounds


def show_dual_domain(target, volume_view=None, sample_size=20000, point_size=3,
                     widget_opacity=0.35):
    """Shows the reduced domain beside the volume: splits the volume view's layout cell
    and puts a render view with the domain's point cloud (a sample of `sample_size`
    voxels at their reduced coordinates, coloured by the widgets over grey) and the
    widgets as translucent spheres (diameter 2 sigma, the widget's colour). The view is
    framed on the points without their far outliers (points cut off from the rest by an
    empty gap) and on the widgets: ReducedDomain's FocusBounds. Reset Camera shows every
    point, far outliers included.

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
    _same_background(volume_view, domain_view)
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
    with _TracedProperties(points):
        points.MapScalars = 0  # the colours themselves, not a colour map
        points.PointSize = point_size
    glyph = simple.Glyph(Input=simple.OutputPort(domain, 1), GlyphType="Sphere")
    with _TracedProperties(glyph):
        glyph.ScaleArray = ["POINTS", "Diameter"]
        glyph.ScaleFactor = 1.0
        glyph.GlyphMode = "All Points"
        # smooth spheres: the default 8 x 8 facets read as octagons at figure size
        glyph.GlyphType.ThetaResolution = 32
        glyph.GlyphType.PhiResolution = 32
    spheres = simple.Show(glyph, domain_view)
    simple.ColorBy(spheres, ("POINTS", "Color"))
    with _TracedProperties(spheres):
        spheres.MapScalars = 0
        spheres.Opacity = widget_opacity
    # The points and spheres show the widgets' own colours (MapScalars off): a colour bar
    # of their values would mean nothing (the GUI may have shown one on Show).
    for rep in (points, spheres):
        rep.SetScalarBarVisibility(domain_view, False)
    simple.ResetCamera(domain_view)
    simple.Render(domain_view)
    if _frame_focus(domain, domain_view) is not None:
        simple.Render(domain_view)

    follower = None
    if display is not None:
        def recolour():
            with _TracedProperties(domain):
                domain.GaussianWidgets = _widget_values(display)
            simple.Render(domain_view)
        follower = _Follower(display, "GaussianWidgets", recolour)
    _followers.append(follower)
    return ViewpointResult(filter=domain, glyph=glyph, domain_view=domain_view, layout=layout,
                           volume_view=volume_view, domain_display=points,
                           widget_display=spheres,
                           stop=(follower.stop if follower else (lambda: None)))
