"""The main job's figures (Examples/transfer_function.py): the eigenvalue spectrum of the
reduction, and the reduced domains of PCA, Isomap, LLE and UMAP side by side.

Drawn with matplotlib (Agg, no display): ParaView's chart views cannot colour some bars of
one series differently, and matplotlib renders the same under pvbatch as anywhere else.
Import it from an example with ``sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))``.
"""
import collections
import math
import textwrap

# Bar colours, written into report.json so a test can count their pixels.
KEPT_COLOUR = (214, 39, 40)     # the OutputDimension leading eigenvalues
OTHER_COLOUR = (31, 119, 180)   # the ones the reduction drops
SPECTRUM_BARS = 20              # leading eigenvalues shown (Isomap has one per landmark)


def _pyplot():
    try:
        import matplotlib
    except ImportError:
        raise SystemExit("matplotlib is needed for spectrum.png and methods.png: "
                         "apt-get install python3-matplotlib (scripts/setup.sh does)")
    matplotlib.use("Agg")
    from matplotlib import pyplot

    return pyplot


def _rgb(colour):
    return tuple(c / 255.0 for c in colour)


def spectrum_table(reduction):
    """(values, fractions) of the Spectrum output (port 1) of a DimensionReduction proxy:
    eigenvalues in the filter's order and each one's share of the positive ones (0 for
    LLE, whose eigenvalues are no variances)."""
    from paraview import servermanager

    table = servermanager.Fetch(reduction, idx=1)
    values = table.GetColumnByName("value")
    fractions = table.GetColumnByName("fraction")
    n = table.GetNumberOfRows()
    return ([values.GetValue(i) for i in range(n)], [fractions.GetValue(i) for i in range(n)])


def _spectrum_text(method, values, kept, variance_retained):
    """Title, y label and the bars' heights: shares in % for PCA / Isomap, the raw
    eigenvalues for LLE (no variance spectrum: it keeps the bottom eigenvectors)."""
    if method == "LLE":
        title = ("LLE: the %d smallest non-trivial eigenvalues of (I-W)$^T$(I-W)\n"
                 "no variance spectrum (LLE keeps the bottom eigenvectors)" % len(values))
        return title, "eigenvalue", list(values)
    if method == "UMAP":
        title = ("UMAP: the %d normalised-Laplacian eigenvalues of its spectral start\n"
                 "no variance spectrum (the layout is optimised from there)" % len(values)
                 if values else "UMAP: random start (its neighbour graph is in pieces)\nno spectrum")
        return title, "eigenvalue", list(values)
    positive = sum(v for v in values if v > 0)
    negative = sum(1 for v in values if v < 0)
    shown = min(len(values), SPECTRUM_BARS)
    title = ("%s eigenvalue spectrum: %.1f%% of the variance retained by the %d kept\n"
             % (method, 100.0 * variance_retained, kept))
    title += ("the leading %d of %d eigenvalues" % (shown, len(values)) if shown < len(values)
              else "all %d eigenvalues" % len(values))
    if negative:
        title += " (%d negative: geodesic distances are not Euclidean)" % negative
    heights = [100.0 * max(0.0, v) / positive if positive > 0 else 0.0 for v in values]
    return title, "share of the positive eigenvalues (%)", heights


def spectrum_figure(path, method, values, kept, variance_retained, size=(900, 560)):
    """Bar chart of the leading eigenvalues, the `kept` ones in KEPT_COLOUR, the others in
    OTHER_COLOUR, the variance retained in the title. Returns the number of bars."""
    plt = _pyplot()
    title, ylabel, heights = _spectrum_text(method, values, kept, variance_retained)
    heights = heights[:SPECTRUM_BARS]
    index = list(range(1, len(heights) + 1))
    colours = [_rgb(KEPT_COLOUR if i <= kept else OTHER_COLOUR) for i in index]
    fig, ax = plt.subplots(figsize=(size[0] / 100.0, size[1] / 100.0), dpi=100)
    ax.bar(index, heights, color=colours, width=0.8, antialiased=False)
    ax.set_ylim(0.0, 1.2 * max(heights + [1e-30]))  # room for the legend above the bars
    ax.set_xticks(index)
    ax.set_xlabel("eigenvalue index")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=11)
    legend = [plt.Rectangle((0, 0), 1, 1, color=_rgb(KEPT_COLOUR))]
    labels = ["kept (the %d reduced coordinates)" % kept]
    if len(heights) > kept:
        legend.append(plt.Rectangle((0, 0), 1, 1, color=_rgb(OTHER_COLOUR)))
        labels.append("dropped")
    ax.legend(legend, labels, loc="upper right")
    ax.grid(axis="y", alpha=0.3)
    ax.set_axisbelow(True)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return len(heights)


def _panel_title(name, variance_retained, trustworthiness, variance_spectrum):
    variance = ("variance retained %.1f%%" % (100.0 * variance_retained)
                if variance_spectrum else "variance retained: n/a")
    trust = ("trustworthiness %.3f" % trustworthiness if math.isfinite(trustworthiness)
             else "trustworthiness n/a")
    return "%s\n%s, %s" % (name, variance, trust)


def widget_colours(points, widgets):
    """Per point (reduced coordinates): the colour (0..255) of the shown widget whose
    Gaussian is the largest there where it reaches half its peak (within 1.18 sigma of
    its centre), else grey. `widgets`: the flat GaussianWidgets list (8 numbers each; a
    hidden widget has opacity 0). Each widget's own voxels in full colour whatever its
    peak opacity: a threshold on the opacity drew none of a faint widget's (the brain's
    "ch2 mid" at 0.09), and the blend of the domain view is too pale in a small plot."""
    shown = [widgets[i:i + 8] for i in range(0, len(widgets) - 7, 8) if widgets[i + 7] > 0]
    colours = []
    for p in points:
        best, colour = 0.5, GREY
        for cx, cy, cz, sigma, r, g, b, _ in shown:
            d2 = sum((x - m) ** 2 for x, m in zip(p, (cx, cy, cz)))
            weight = math.exp(-d2 / (2.0 * sigma * sigma))
            if weight >= best:
                best, colour = weight, tuple(int(round(255 * v)) for v in (r, g, b))
        colours.append(colour)
    return colours


GREY = (190, 190, 190)


def methods_figure(path, panels, caption, size=None):
    """One scatter plot per method (dimensions 1 and 2 of its reduced domain) of the same
    sampled voxels in the same colours, 500 x 600 pixels each unless `size` says. `panels`:
    dicts with name, x, y, colours (RGB 0..255 per point), variance_retained,
    trustworthiness. Grey voxels (no widget) are drawn first so the coloured ones stay on
    top, and the colours of fewer points over those of more."""
    plt = _pyplot()
    size = size or (500 * len(panels), 600)
    fig, axes = plt.subplots(1, len(panels), figsize=(size[0] / 100.0, size[1] / 100.0),
                             dpi=100)
    for ax, panel in zip(axes, panels):
        colours = panel["colours"]
        # grey first, then each colour by how many points it has, the rarest on top
        count = collections.Counter(colours)
        order = sorted(range(len(colours)),
                       key=lambda i: (_spread(colours[i]) > 0, -count[colours[i]]))
        ax.scatter([panel["x"][i] for i in order], [panel["y"][i] for i in order],
                   c=[_rgb(colours[i]) for i in order], s=3, linewidths=0)
        ax.set_title(_panel_title(panel["name"], panel["variance_retained"],
                                  panel["trustworthiness"], panel["variance_spectrum"]),
                     fontsize=11)
        ax.set_xlabel("dimension 1")
        ax.set_ylabel("dimension 2")
        ax.tick_params(labelsize=8)
    fig.suptitle(textwrap.fill(caption, 130), fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def _spread(rgb):
    """How far a colour is from grey: 0 for voxels no widget selects."""
    return max(rgb) - min(rgb)
