"""Widget seeding: Gaussian widgets placed at the k-means cluster centres of the reduced
domain.
"""

from ._common import _TracedProperties
from .dual_domain import reduced_domain_filter
from .transfer_function import _coordinates_name, _source_and_display, check_widget_values

__all__ = [
    "auto_widgets",
]


def auto_widgets(target, count=4, view=None, opacity=0.5, seed=0, sample_size=20000,
                 skip_background=True):
    """Seeds `count` Gaussian widgets at the k-means cluster centres of the reduced domain
    (largest cluster first, colours of ColorBrewer Set1, sigma = each cluster's spread
    capped at a quarter of the distance to the nearest other cluster, peak `opacity`, the
    largest of several widgets 0.05 x `opacity`: a veil over what it holds).
    Voxels the volume's Foreground array (MultichannelFeatures' MaskBackground, on by
    default) marks as background are left out. Without such an array, `skip_background`
    (default) makes count + 1 clusters and leaves the largest, almost always the volume's
    background, without a widget; with one it has no effect.

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
    check_widget_values(widgets, "auto_widgets (ReducedDomain's SeededWidgets)")
    if display is not None:
        with _TracedProperties(display):  # recorded in a trace being recorded
            display.GaussianWidgets = widgets
    return widgets
