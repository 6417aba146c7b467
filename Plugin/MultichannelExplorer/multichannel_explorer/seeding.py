"""Widget seeding: Gaussian widgets placed at the k-means cluster centres of the reduced
domain, with opacities that let inner structures show, the background-sized class hidden,
and names that say what each widget selects.
"""

from collections import Counter

from ._common import _TracedProperties, _view_time
from ._voxels import _NOT_CHANNELS, _fetch_voxels, label_tables
from .dual_domain import reduced_domain_filter
from .transfer_function import _coordinates_name, _source_and_display, check_widget_values

__all__ = [
    "auto_widgets",
    "label_channels",
    "widget_names",
]

# A label names a widget when at least this fraction of the widget's voxels carry it.
LABEL_SHARE = 0.25
# A channel without a label table is an atlas (its values are labels, not intensities)
# when its values are integers and the volume is piecewise constant in it: of the sampled
# voxels whose value or next voxel's value (along x) is not 0, at least this fraction
# have the same value as that neighbour. The number of distinct values does not tell: AAL
# has 116 labels and the 8-bit Colin27 T1 (ch2) 249 integers. Neighbours do: measured on
# the whole volumes (181 x 217 x 181, along x, y and z) ch2 keeps its neighbour's value at
# 9-10 % of such voxel pairs (noise and smooth grey levels), AAL at 89-92 % and Brodmann
# at 89-90 % (regions thousands of voxels large): 0.5 lies far from both.
LABEL_SAME_NEIGHBOUR = 0.5
# Without neighbour values (widget_names called on a sample alone), a channel without a
# table is an atlas when its sample holds at most this many distinct integers (Brodmann's
# 42 values are; AAL's 116 are not: give its neighbours, or its label table).
LABEL_VALUES = 64
# At most this many of the sample's voxels have their neighbours read (one server round trip).
NEIGHBOUR_SAMPLE = 4000
# A widget draws an atlas's region borders when at least this share of its points whose
# neighbours were read lie on one (a face neighbour with another label), twice the
# sample's share at least, and at least MIN_READ of them were read. Measured on the main
# job's brain (24D Isomap, 4 widgets): two small widgets had 100 % of their voxels on the
# AAL, resp. Brodmann borders, the other two 5 % and 20 %; the sample 12-14 %.
BOUNDARY_SHARE = 0.75
MIN_READ = 5
# A widget selects what lies around an atlas when at least this share of its points have
# the atlas's 0 (main job: the hidden widget 94-96 %, the sample 65-68 %).
OUTSIDE_SHARE = 0.75


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


def _channel_candidates(columns):
    """The one-component channels of a sample's columns (not SeededWidget, VoxelId...)."""
    return [c for c, v in columns.items()
            if c not in _NOT_CHANNELS and v and len(v[0]) == 1
            and c not in ("SeededWidget", "WidgetOpacity", "VoxelId")]


def label_channels(columns, tables, neighbours=None):
    """The atlas (label) channels among a sample's one-component channels: those with a
    label table, and those whose values are all integers and that are piecewise constant:
    at least LABEL_SAME_NEIGHBOUR of the points whose value or neighbour's value is not 0
    have the same value as their neighbour. `columns`: {array: per-point tuples} (the
    ReducedDomain sample); `tables`: {channel: {value: label}} (label_tables);
    `neighbours`: {channel: per-point value of the next voxel along x, None where not
    read} (auto_widgets reads them). Without `neighbours`, a channel without a table is an
    atlas when its sample holds at most LABEL_VALUES distinct integers. Returns a list."""
    atlases = []
    for channel in _channel_candidates(columns):
        values = [v[0] for v in columns[channel]]
        if channel in tables:
            atlases.append(channel)
            continue
        if not all(float(v).is_integer() for v in values):
            continue
        if neighbours is None or channel not in neighbours:
            if len(set(values)) <= LABEL_VALUES:
                atlases.append(channel)
            continue
        pairs = [(v, n) for v, n in zip(values, neighbours[channel])
                 if n is not None and (v != 0 or n != 0)]
        same = sum(1 for v, n in pairs if v == n)
        if pairs and same >= LABEL_SAME_NEIGHBOUR * len(pairs):
            atlases.append(channel)
    return atlases


def _neighbourhoods(source, columns):
    """What the voxels around the sampled ones hold, for at most NEIGHBOUR_SAMPLE points of
    the sample, evenly spread, read with one ExtractVoxels by global voxel id (right on
    every process count). Returns (neighbours, boundaries), each {channel: per-point list,
    None for the points not read}: neighbours, the value of the voxel after the point
    along x (before it for the last voxel of a row), which tells atlases (label_channels);
    boundaries, whether one of the point's face neighbours inside the grid (up to six)
    holds another value: a voxel on the border between two regions of an atlas
    (widget_names). (None, None) without VoxelId."""
    ids = columns.get("VoxelId")
    if not ids:
        return None, None
    extent = [int(v) for v in source.GetDataInformation().GetExtent()]
    size = [extent[2 * a + 1] - extent[2 * a] + 1 for a in range(3)]
    strides = (1, size[0], size[0] * size[1])
    step = max(1, len(ids) // NEIGHBOUR_SAMPLE)
    around = {}  # point -> (the next voxel along x, its face neighbours)
    for p in range(0, len(ids), step):
        voxel = int(ids[p][0])
        ijk = (voxel % size[0], voxel // size[0] % size[1], voxel // strides[2])
        faces = [voxel + d * strides[a] for a in range(3) for d in (-1, 1)
                 if 0 <= ijk[a] + d < size[a]]
        if not faces:
            continue  # a single voxel
        after = voxel + 1 if ijk[0] < size[0] - 1 else voxel - 1
        around[p] = (after if size[0] > 1 else None, faces)
    wanted = sorted({v for after, faces in around.values() for v in faces})
    voxels = _fetch_voxels(source, wanted)
    pd = voxels.GetPointData()
    found = pd.GetArray("VoxelId")
    row = {int(found.GetValue(r)): r for r in range(found.GetNumberOfTuples())} if found else {}
    neighbours, boundaries = {}, {}
    for channel in _channel_candidates(columns):
        array = pd.GetArray(channel)
        if array is None:
            continue
        values = [None] * len(ids)
        border = [None] * len(ids)
        for p, (after, faces) in around.items():
            if after is not None and after in row:
                values[p] = array.GetTuple1(row[after])
            read = [array.GetTuple1(row[v]) for v in faces if v in row]
            if read:
                border[p] = any(v != columns[channel][p][0] for v in read)
        neighbours[channel] = values
        boundaries[channel] = border
    return neighbours, boundaries


def _shares(flags, rows):
    """(share of True among the read flags of `rows`, how many were read)."""
    read = [flags[p] for p in rows if flags[p] is not None]
    return (float(sum(read)) / len(read) if read else 0.0), len(read)


def _boundary_name(rows, atlases, boundaries, everyone):
    """'<atlas> boundaries' when most of the widget's read points lie on a border between
    two regions of an atlas (BOUNDARY_SHARE) and at least twice the sample's share do:
    the widget draws the atlas's region borders (the features' local statistics of a
    label channel are large there). None otherwise."""
    best = None
    for channel in atlases:
        flags = (boundaries or {}).get(channel)
        if not flags:
            continue
        share, read = _shares(flags, rows)
        overall, _ = _shares(flags, everyone)
        if read >= MIN_READ and share >= BOUNDARY_SHARE and share >= 2.0 * overall and (
                best is None or share > best[0]):
            best = (share, "%s boundaries" % channel)
    return best[1] if best else None


def _label_name(rows, atlases, columns, tables):
    """The most frequent non-zero label of an atlas that at least LABEL_SHARE of the
    widget's points carry: its name in the table, else '<channel> <value>'; None."""
    best = None
    for channel in atlases:
        values = Counter(int(round(columns[channel][p][0])) for p in rows)
        values.pop(0, None)
        if values:
            value, hits = values.most_common(1)[0]
            share = float(hits) / len(rows)
            if share >= LABEL_SHARE and (best is None or share > best[0]):
                best = (share, tables.get(channel, {}).get(value, "%s %d" % (channel, value)))
    return best[1] if best else None


def _outside_name(rows, atlases, columns):
    """'outside <atlas>' when at least OUTSIDE_SHARE of the widget's points have the
    atlas's 0 (no region) and its labelled share is at most half the sample's: the
    widget selects what lies around the atlas (scalp and skull around a brain). None."""
    best = None
    everyone = len(next(iter(columns.values()), ()))
    for channel in atlases:
        zero = sum(1 for p in rows if columns[channel][p][0] == 0)
        overall = sum(1 for v in columns[channel] if v[0] == 0)
        share = float(zero) / len(rows)
        if share >= OUTSIDE_SHARE and (1.0 - share) <= 0.5 * (1.0 - float(overall) / everyone) \
                and (best is None or share > best[0]):
            best = (share, "outside %s" % channel)
    return best[1] if best else None


def _intensity_name(rows, candidates, atlases, columns):
    """(name, channel, median, z): the channel, not an atlas, that sets the widget apart
    most (the largest (mean over the widget - mean over the sample)^2 / variance over the
    widget), called '<channel> bright', 'dark' or 'mid' by z, the widget's mean against
    the sample's in standard deviations of the sample (beyond +-0.5: bright, dark); None."""
    apart = None
    for channel in candidates:
        if channel in atlases:
            continue
        values = columns[channel]
        everything = [v[0] for v in values]
        mean = sum(everything) / len(everything)
        spread = (sum((v - mean) ** 2 for v in everything) / len(everything)) ** 0.5
        if spread <= 0:
            continue
        inside = [values[p][0] for p in rows]
        inner_mean = sum(inside) / len(inside)
        inner_var = sum((v - inner_mean) ** 2 for v in inside) / len(inside)
        score = (inner_mean - mean) ** 2 / max(inner_var, 1e-12 * spread * spread)
        if apart is None or score > apart[0]:
            apart = (score, channel, (inner_mean - mean) / spread, _median(inside))
    if apart is None:
        return None
    _, channel, z, median = apart
    level = "bright" if z > 0.5 else "dark" if z < -0.5 else "mid"
    return "%s %s" % (channel, level), channel, median, z


def widget_names(columns, count, tables, neighbours=None, boundaries=None):
    """Names for `count` seeded widgets from what their sampled voxels hold.

    `columns`: {array: per-point tuples} of the ReducedDomain sample, with SeededWidget
    (the widget of each point); `tables`: {channel: {value: label}} (label_tables);
    `neighbours`: the next voxels' values that tell atlases without a table
    (label_channels); `boundaries`: {channel: per-point True where a face neighbour holds
    another value, None where not read} (_neighbourhoods). For each widget, the first of:
    - '<atlas> boundaries': most of its points on the borders between an atlas's regions
      (BOUNDARY_SHARE, and twice the sample's share);
    - an atlas label: the most frequent non-zero value of an atlas channel, when at least
      LABEL_SHARE of the widget's points carry it: its label ("Precentral_L"), or
      "<channel> <value>" without a table ("brodmann 4");
    - the channel, not an atlas, that sets the widget apart most, when the widget is
      bright or dark in it: "<channel> bright" (its mean more than half a standard
      deviation of the sample above the sample's), "<channel> dark" (below);
    - 'outside <atlas>': most of its points (OUTSIDE_SHARE) outside every region of an
      atlas, at most half the sample's labelled share inside;
    - "<channel> mid" for that channel; else "Widget N".
    Widgets that get the same name are told apart by the median of that channel
    ("ch2 bright ~96", "ch2 bright ~131"); the others by the median of the channel that
    sets each apart ("aal boundaries (ch2 ~73)") where those differ, else by a number.
    Returns the list."""
    labels = columns.get("SeededWidget")
    candidates = _channel_candidates(columns)
    atlases = label_channels(columns, tables, neighbours)
    everyone = range(len(labels or ()))
    named = []  # (name, channel or None, median, intensity: (channel, median) or None)
    for w in range(count):
        rows = [p for p, v in enumerate(labels or ()) if int(v[0]) == w]
        if not rows:
            named.append(("Widget %d" % (w + 1), None, 0.0, None))
            continue
        intensity = _intensity_name(rows, candidates, atlases, columns)
        level = (intensity[1], intensity[2]) if intensity is not None else None
        name = (_boundary_name(rows, atlases, boundaries, everyone) or
                _label_name(rows, atlases, columns, tables))
        if name is not None:
            named.append((name, None, 0.0, level))
            continue
        outside = _outside_name(rows, atlases, columns)
        if intensity is not None and (abs(intensity[3]) > 0.5 or outside is None):
            named.append(intensity[:3] + (level,))
        elif outside is not None:
            named.append((outside, None, 0.0, level))
        else:
            named.append(("Widget %d" % (w + 1), None, 0.0, None))
    names = []
    for w, (name, channel, median, level) in enumerate(named):
        twins = [n for n in named if n[0] == name]
        if len(twins) > 1:
            # Told apart by the median of the channel that sets each apart ("aal boundaries
            # (ch2 ~73)"), when those differ; else numbered in order.
            levels = ["%s ~%.3g" % t[3] if t[3] else None for t in twins]
            before = sum(1 for n in named[:w] if n[0] == name)
            if channel is not None:
                name = "%s ~%.3g" % (name, median)
            elif None not in levels and len(set(levels)) == len(levels):
                name = "%s (%s)" % (name, levels[before])
            else:
                name = "%s %d" % (name, before + 1)
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
    atlas label, else the channel that sets it apart; atlases are the channels with a
    label table or piecewise constant in integers, label_channels) in GaussianWidgetNames.
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
    domain.UpdatePipeline(_view_time(view))  # the time step on screen
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
        columns = _cloud_columns(servermanager.Fetch(domain))
        neighbours, boundaries = _neighbourhoods(source, columns)
        names = widget_names(columns, seeded, label_tables(_fetch_voxels(source, [0])),
                             neighbours, boundaries)
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
