"""Widget seeding: Gaussian widgets placed at the k-means cluster centres of the reduced
domain, with opacities that let inner structures show, the background-sized class hidden,
and names that say what each widget selects.
"""

from collections import Counter

from ._common import _TracedProperties
from ._voxels import _NOT_CHANNELS, _fetch_voxels, label_tables
from .dual_domain import reduced_domain_filter
from .transfer_function import _coordinates_name, _source_and_display, check_widget_values

__all__ = [
    "auto_widgets",
    "widget_names",
]

# A label names a widget when at least this fraction of the widget's voxels carry it.
LABEL_SHARE = 0.25
# A channel without a label table whose sample holds at most this many distinct integers
# is an atlas too (its values are labels, not intensities).
LABEL_VALUES = 64


def _cloud_columns(cloud):
    """{array name: list of tuples} of the domain cloud's point arrays."""
    pd = cloud.GetPointData()
    columns = {}
    for a in range(pd.GetNumberOfArrays()):
        array = pd.GetArray(a)
        if array is None or array.GetName() is None:
            continue
        columns[array.GetName()] = [array.GetTuple(t) for t in range(array.GetNumberOfTuples())]
    return columns


def _median(values):
    ordered = sorted(values)
    return ordered[len(ordered) // 2] if ordered else 0.0


def widget_names(columns, count, tables):
    """Names for `count` seeded widgets from what their sampled voxels hold.

    `columns`: {array: per-point tuples} of the ReducedDomain sample, with SeededWidget
    (the widget of each point); `tables`: {channel: {value: label}} (label_tables). For
    each widget:
    - an atlas label: the most frequent non-zero value of an atlas channel (one with a
      label table, or whose sample holds at most LABEL_VALUES distinct integers), when
      at least LABEL_SHARE of the widget's points carry it: its label ("Precentral_L"),
      or "<channel> <value>" without a table ("brodmann 4");
    - else the one-component channel, not an atlas, that sets the widget apart most:
      the largest (mean over the widget - mean over the sample)^2 / variance over the
      widget (a channel whose values the widget holds tight and away from the rest,
      e.g. a T1 intensity; not an atlas whose labels vary inside it): "<channel> bright"
      (its mean more than half a standard deviation of the sample above the sample's),
      "<channel> dark" (below) or "<channel> mid";
    - else "Widget N".
    Widgets that get the same name are told apart by the median of that channel
    ("ch2 bright ~96", "ch2 bright ~131") or, for labels, a number. Returns the list."""
    labels = columns.get("SeededWidget")
    candidates = [c for c, v in columns.items()
                  if c not in _NOT_CHANNELS and v and len(v[0]) == 1
                  and c not in ("SeededWidget", "WidgetOpacity", "VoxelId")]
    # Label channels: those with a table, and those whose sample holds at most
    # LABEL_VALUES distinct integers (an atlas without a label file, e.g. Brodmann's).
    atlases = [c for c in candidates if c in tables or (
        len(set(v[0] for v in columns[c])) <= LABEL_VALUES
        and all(float(v[0]).is_integer() for v in columns[c]))]
    named = []  # (name, channel or None, median)
    for w in range(count):
        rows = [p for p, v in enumerate(labels or ()) if int(v[0]) == w]
        best = None
        for channel in atlases:
            if not rows:
                continue
            values = Counter(int(round(columns[channel][p][0])) for p in rows)
            values.pop(0, None)
            if values:
                value, hits = values.most_common(1)[0]
                share = float(hits) / len(rows)
                table = tables.get(channel, {})
                if share >= LABEL_SHARE and (best is None or share > best[0]):
                    best = (share, table.get(value, "%s %d" % (channel, value)))
        if best is not None:
            named.append((best[1], None, 0.0))
            continue
        apart = None
        for channel in candidates:
            values = columns[channel]
            if not rows or channel in atlases:
                continue
            everything = [v[0] for v in values]
            mean = sum(everything) / len(everything)
            spread = (sum((v - mean) ** 2 for v in everything) / len(everything)) ** 0.5
            inside = [values[p][0] for p in rows]
            inner_mean = sum(inside) / len(inside)
            inner_var = sum((v - inner_mean) ** 2 for v in inside) / len(inside)
            if spread <= 0:
                continue
            score = (inner_mean - mean) ** 2 / max(inner_var, 1e-12 * spread * spread)
            if apart is None or score > apart[0]:
                apart = (score, channel, (inner_mean - mean) / spread, _median(inside))
        if apart is None:
            named.append(("Widget %d" % (w + 1), None, 0.0))
            continue
        _, channel, z, median = apart
        named.append(("%s %s" % (channel, "bright" if z > 0.5 else "dark" if z < -0.5
                                 else "mid"), channel, median))
    names = []
    for w, (name, channel, median) in enumerate(named):
        twins = [n for n in named if n[0] == name]
        if len(twins) > 1:
            name = ("%s ~%.3g" % (name, median) if channel is not None
                    else "%s %d" % (name, twins.index(named[w]) + 1))
        names.append(name)
    return names


def auto_widgets(target, count=4, view=None, opacity=0.5, seed=0, sample_size=20000,
                 skip_background=True):
    """Seeds `count` Gaussian widgets at the k-means cluster centres of the reduced domain
    (largest cluster first, colours of ColorBrewer Set1, sigma = each cluster's spread
    capped at a quarter of the distance to the nearest other cluster). Peak opacities
    are derived from what each widget selects, at most `opacity`: a widget whose voxels a
    typical ray through the volume crosses many of lets half of the light through
    (WidgetSeeding.h: a = (1 - 0.5^(1 / (s L))) / g for share s, mean ray length L,
    mean Gaussian weight g). The widget of a cluster of more than half of the voxels
    (the class around the others: scalp and skull around a brain) starts hidden: opacity
    0 in GaussianWidgets, its opacity kept in GaussianWidgetsHidden (the editor's check
    box shows it again). Each widget is named after what it selects (widget_names: an
    atlas label, else the channel that sets it apart) in GaussianWidgetNames.
    Voxels the volume's Foreground array (MultichannelFeatures' MaskBackground, on by
    default) marks as background are left out. Without such an array, `skip_background`
    (default) makes count + 1 clusters and leaves the largest, almost always the volume's
    background, without a widget; with one it has no effect.

    `target` is a volume with ReducedCoordinates or its "Gaussian TF Volume" display; when
    a display is given (or the volume is shown as one in `view`), its GaussianWidgets,
    GaussianWidgetsHidden and GaussianWidgetNames are set. Returns the flat widget list as
    drawn (8 numbers per widget: cx, cy, cz, sigma, r, g, b, opacity; a hidden widget has
    opacity 0, the one it gets when shown is in GaussianWidgetsHidden and in the
    ReducedDomain's SeededWidgets)::

        display = mce.show_gaussian_tf(reduction, view)
        mce.auto_widgets(display, 3)
    """
    from paraview import servermanager

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
    details = [float(v) for v in domain.GetProperty("SeededWidgetDetails")]
    if not widgets:
        domain.SeedWidgetCount = 0
        raise RuntimeError("auto_widgets: no widgets could be seeded (see the messages of "
                           "ReducedDomain)")
    seeded = len(widgets) // 8
    check_widget_values(widgets, "auto_widgets (ReducedDomain's SeededWidgets)")
    names = None
    if display is not None:
        # The sample with each point's widget, fetched before the seeding is switched off
        # (later updates only recolour and drop SeededWidget).
        names = widget_names(_cloud_columns(servermanager.Fetch(domain)), seeded,
                             label_tables(_fetch_voxels(source, [0])))
    domain.SeedWidgetCount = 0  # one suggestion; later updates only recolour
    hidden = [-1.0] * seeded
    drawn = list(widgets)
    for w in range(seeded):
        if len(details) >= 3 * (w + 1) and details[3 * w + 1] > 0 and widgets[8 * w + 7] > 0:
            hidden[w] = widgets[8 * w + 7]
            drawn[8 * w + 7] = 0.0
    if display is None:
        return drawn
    with _TracedProperties(display):  # recorded in a trace being recorded
        display.GaussianWidgets = drawn
        display.GaussianWidgetsHidden = hidden if any(h >= 0 for h in hidden) else []
        display.GaussianWidgetNames = names
    with _TracedProperties(domain):
        # The domain colours by the display's widgets (without any, its next update would
        # warn of a transparent volume while the display has widgets).
        domain.GaussianWidgets = drawn
    return drawn
