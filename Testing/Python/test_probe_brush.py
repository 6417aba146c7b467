"""Probing and brushing: linking the volume and its reduced domain.

(1) Synthetic volume with known ReducedCoordinates (a resampled Wavelet: spacing
    (1, 0.5, 1.5), origin (-3, 0, 1), so indices, ids and positions differ): probe() of a
    voxel by index, point id and world position returns that voxel's own coordinates,
    channel, Features and Foreground (read from the fetched volume); the marker in the
    domain view sits at its coordinates and is moved, not duplicated; add_widget_at
    appends one widget there with a palette colour no widget has (the palette equals the
    core's: compared with auto_widgets' seeded colours); probe_at_pixel finds the voxel
    projected to a pixel and probe_domain_at_pixel the voxel of the cloud point seen at a
    pixel of the domain view; brush() by VoxelIds, by a box (expected set from the volume's
    arrays) and by ParaView's selection of the domain cloud (SelectIDs, and a frustum
    rubber band SelectPointsThrough in the domain view = a box in reduced coordinates).
(2) The real brain (Colin27 T1 + AAL + Brodmann -> 6D features -> Isomap, reference 2000,
    200 landmarks): probe a voxel -> its ReducedCoordinates (read directly); brush a box of
    the domain -> the voxels whose ReducedCoordinates (volume array, at the cloud's
    VoxelIds) lie in it.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402
import builtins as B  # noqa: E402

from paraview import servermanager  # noqa: E402
from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_probe_brush")
out = T.output_dir()


def close(a, b, tol=1e-6):
    a, b = list(a), list(b)
    return len(a) == len(b) and all(abs(x - y) <= tol for x, y in zip(a, b))


def highlighted_ids():
    """Voxel ids (of the volume) of what brush() shows, read from its extract."""
    extract = simple.FindSource(mce.BRUSHED_VOXELS)
    data = servermanager.Fetch(extract)
    ids = data.GetPointData().GetArray("VoxelId")
    return B.set(int(ids.GetValue(p)) for p in range(ids.GetNumberOfTuples())) if ids else B.set()


# ---- (1) synthetic ------------------------------------------------------------------------
wavelet = simple.Wavelet(WholeExtent=[-10, 20, -10, 20, -10, 20])  # covers the grid
grid = simple.ResampleToImage(Input=wavelet, UseInputBounds=0,
                              SamplingBounds=[-3, 12, 0, 5.5, 1, 14.5],
                              SamplingDimensions=[16, 12, 10])
coords_f = simple.Calculator(Input=grid, ResultArrayName="ReducedCoordinates",
                             ResultArrayType="Float",
                             Function="(0.1*coordsX)*iHat + (0.2*coordsY*coordsY)*jHat"
                                      " + (RTData/250)*kHat")
feats_f = simple.Calculator(Input=coords_f, ResultArrayName="Features", ResultArrayType="Float",
                            Function="coordsX*iHat + (coordsY+coordsZ)*jHat")
volume = simple.Calculator(Input=feats_f, ResultArrayName="Foreground",
                           ResultArrayType="Unsigned Char", Function="coordsX > 0")
volume.UpdatePipeline()
full = servermanager.Fetch(volume)
dims = full.GetDimensions()
pd = full.GetPointData()
rc = pd.GetArray("ReducedCoordinates")
C.check(tuple(dims) == (16, 12, 10) and close(full.GetSpacing(), (1, 0.5, 1.5)),
        "synthetic grid 16x12x10, spacing (1, 0.5, 1.5)")

view = G.black_view((500, 400))
colors = [mce.palette_color(0), mce.palette_color(1)]
display = mce.show_gaussian_tf(volume, view, widgets=[
    [0.5, 2.0, 0.3, 5.0] + colors[0] + [1.0], [-0.2, 0.5, 0.3, 0.2] + colors[1] + [0.5]])
dual = mce.show_dual_domain(display, view, sample_size=100000)  # every foreground voxel

i, j, k = 11, 7, 4
pid = i + dims[0] * (j + dims[1] * k)
position = full.GetPoint(pid)
expected = dict(coordinates=list(rc.GetTuple3(pid)), features=list(pd.GetArray("Features").GetTuple(pid)),
                foreground=int(pd.GetArray("Foreground").GetValue(pid)),
                rtdata=float(pd.GetArray("RTData").GetValue(pid)))
nudged = [position[0] + 0.3, position[1] - 0.2, position[2] + 0.7]  # still nearest to it
for label, arg in (("index", (i, j, k)), ("point id", pid), ("world position", nudged)):
    hit = mce.probe(display, arg)
    C.check(tuple(hit.index) == (i, j, k) and hit.point_id == pid and
            close(hit.position, position), "probe by %s: voxel (%d, %d, %d), id %d, position %s"
            % (label, i, j, k, pid, ["%.2f" % v for v in hit.position]))
    C.check(close(hit.coordinates, expected["coordinates"]) and
            close(hit.features, expected["features"]) and
            hit.foreground == expected["foreground"] == 1 and
            close([hit.channels["RTData"]], [expected["rtdata"]]),
            "probe by %s: that voxel's ReducedCoordinates %s, Features, Foreground, RTData"
            % (label, ["%.4f" % v for v in hit.coordinates]))
marker = simple.FindSource(mce.PROBE_MARKER)
marker_rep = servermanager.GetRepresentation(marker, dual.domain_view) if marker else None
C.check(marker is not None and close(marker.Center, expected["coordinates"]) and
        marker_rep is not None and marker_rep.Visibility,
        "the probe marker sits at the coordinates in the domain view")
simple.SaveScreenshot(os.path.join(out, "probe_synthetic_domain.png"), dual.domain_view,
                      ImageResolution=[400, 400])
other = mce.probe(display, (2, 3, 5))
sources = [n for (n, _) in simple.GetSources().keys() if n == mce.PROBE_MARKER]
C.check(len(sources) == 1 and close(simple.FindSource(mce.PROBE_MARKER).Center, other.coordinates),
        "a second probe moves the one marker (%d marker sources)" % len(sources))
C.check(other.foreground == 0, "a background voxel probes with Foreground 0")
for bad in ((16, 0, 0), dims[0] * dims[1] * dims[2], (1, 2)):
    try:
        mce.probe(display, bad)
        C.check(False, "probe(%r) outside the volume: an error" % (bad,))
    except ValueError as error:
        C.check(True, "probe(%r): %s" % (bad, error))

# add widget here: one more widget, at the probed coordinates, with an unused Set1 colour.
seeding = simple.ReducedDomain(Input=volume, SampleSize=2000, SeedWidgetCount=3)
seeding.UpdatePipeline()
seeding.UpdatePropertyInformation()
seeded = [float(v) for v in seeding.GetProperty("SeededWidgets")]  # the core's palette
simple.Delete(seeding)
C.check(all(close(seeded[8 * w + 4:8 * w + 7], mce.palette_color(w), 1e-6) for w in range(3)),
        "palette_color equals the core's seeded colours (ColorBrewer Set1)")
display.GaussianWidgets = [0.5, 2.0, 0.3, 5.0] + colors[0] + [1.0] + \
    [-0.2, 0.5, 0.3, 0.2] + colors[1] + [0.5]
hit = mce.probe(display, (i, j, k))
before = list(display.GaussianWidgets)
added = mce.add_widget_at(display, hit)
after = [float(v) for v in display.GaussianWidgets]
span = max(rc.GetRange(c)[1] - rc.GetRange(c)[0] for c in range(3))
expected, share = mce.presentable_opacity(volume, hit.coordinates, after[-5])
C.check(len(after) == len(before) + 8 and close(after[:len(before)], before) and
        close(after[-8:-5], hit.coordinates) and abs(after[-5] - 0.05 * span) < 1e-5 and
        0 < after[-1] <= 0.5 and abs(after[-1] - expected) < 1e-9,
        "add_widget_at: one widget appended at the coordinates, sigma 5%% of the range "
        "(%.4f), opacity %.4f = presentable_opacity's (share %.3f), at most 0.5"
        % (after[-5], after[-1], share))
C.check(close(after[-4:-1], mce.palette_color(2)) and
        all(not close(after[-4:-1], c, 1e-3) for c in colors),
        "add_widget_at: a palette colour no widget had (%s)" % ["%.3f" % v for v in after[-4:-1]])

# probe_at_pixel: looking down -z (parallel), the pixel of a voxel's centre picks that
# column; a widget opaque everywhere stops the ray at the first foreground voxel (top).
display.GaussianWidgets = [0, 0, 0, 100.0, 1, 1, 1, 1.0]
bounds = full.GetBounds()
G.look_down_z(view, bounds)
top = i + dims[0] * (j + dims[1] * (dims[2] - 1))
x, y = G.project(view, full.GetPoint(top))
picked = mce.probe_at_pixel(view, x, y)
C.check(picked is not None and tuple(picked.index) == (i, j, dims[2] - 1),
        "probe_at_pixel(%d, %d): the voxel seen there, (%d, %d, %d) (got %s)"
        % (x, y, i, j, dims[2] - 1, picked and tuple(picked.index)))
x0, _ = G.project(view, full.GetPoint(2 + dims[0] * j))  # a background column
bg = mce.probe_at_pixel(view, x0, y)
C.check(bg is None, "probe_at_pixel over background only: None")
C.check(mce.probe_at_pixel(view, 2, 2) is None, "probe_at_pixel off the volume: None")
simple.SaveScreenshot(os.path.join(out, "probe_synthetic_volume.png"), view,
                      ImageResolution=[500, 400])

# brush: explicit VoxelIds, a box, ParaView's selection of the domain cloud.
ids = [pid, 5, 77, 400]
C.check(mce.brush(display, voxel_ids=ids) == 4 and highlighted_ids() == B.set(ids),
        "brush(voxel_ids): those 4 voxels highlighted")
try:
    mce.brush(display, voxel_ids=[3, full.GetNumberOfPoints()])
    C.check(False, "brush(voxel id outside the volume): an error")
except ValueError as error:
    C.check(highlighted_ids() == B.set(ids), "brush(voxel id outside): %s; highlight kept"
            % error)
box = (0.3, 0.9, 0.5, 4.0, -1.0, 1.0)
fg = pd.GetArray("Foreground")
in_box = B.set(p for p in range(full.GetNumberOfPoints()) if fg.GetValue(p) and
               all(box[2 * a] <= rc.GetComponent(p, a) <= box[2 * a + 1] for a in range(3)))
count = mce.brush(display, box=box)
C.check(len(in_box) > 20 and count == len(in_box) and highlighted_ids() == in_box,
        "brush(box): the %d foreground voxels with coordinates in the box (%d)"
        % (len(in_box), count))
extracts = [n for (n, _) in simple.GetSources().keys() if n == mce.BRUSHED_VOXELS]
C.check(len(extracts) == 1, "brushing again replaces the highlight")
cloud = servermanager.Fetch(dual.filter)
voxel_id = cloud.GetPointData().GetArray("VoxelId")
chosen = [3, 10, 50]
simple.SelectIDs(IDs=[v for c in chosen for v in (0, c)], FieldType="POINT", Source=dual.filter)
expected_ids = B.set(int(voxel_id.GetValue(c)) for c in chosen)
C.check(mce.brush(dual.filter) == 3 and highlighted_ids() == expected_ids,
        "brush(ReducedDomain with a selection of 3 cloud points): their 3 voxels")
# A rubber band through the domain view (frustum), camera down -z with parallel
# projection: the rectangle is a box in the first two reduced coordinates.
G.look_down_z(dual.domain_view, cloud.GetBounds())
lo = [0.25, 1.0, 0]  # between the columns and rows of the (regular) cloud
hi = [0.75, 2.8, 0]
(x0, y0), (x1, y1) = G.project(dual.domain_view, lo), G.project(dual.domain_view, hi)
simple.ClearSelection(dual.filter)
simple.SetActiveSource(dual.filter)
simple.SelectPointsThrough(Rectangle=[x0, y0, x1, y1], View=dual.domain_view)
ren = dual.domain_view.GetRenderer()
rubber = B.set()
for p in range(cloud.GetNumberOfPoints()):
    px, py = G.project(dual.domain_view, cloud.GetPoint(p))  # pixel of each cloud point
    if x0 <= px <= x1 and y0 <= py <= y1:
        rubber.add(int(voxel_id.GetValue(p)))
count = mce.brush(dual.filter)
got = highlighted_ids()
C.check(len(rubber) > 10 and count == len(got) and got == rubber,
        "brush after a rubber band in the domain view: %d voxels, the %d whose points' "
        "pixels are in the rectangle (%d differ)" % (count, len(rubber), len(got ^ rubber)))
# Probe in the domain view: the cloud point seen at a pixel (nearest the camera of those
# within 5 pixels of it) -> its voxel.
target = 123
px, py = G.project(dual.domain_view, cloud.GetPoint(target))
near = [p for p in range(cloud.GetNumberOfPoints())
        if max(abs(a - b) for a, b in zip(G.project(dual.domain_view, cloud.GetPoint(p)),
                                          (px, py))) <= 3]
front = max(near, key=lambda p: cloud.GetPoint(p)[2])  # camera on +z
from_domain = mce.probe_domain_at_pixel(dual.domain_view, px, py)
C.check(from_domain is not None and from_domain.point_id == int(voxel_id.GetValue(front)) and
        close(from_domain.coordinates, rc.GetTuple3(from_domain.point_id)),
        "probe_domain_at_pixel: the voxel of the front cloud point at that pixel (%s, expected "
        "%d)" % (from_domain and from_domain.point_id, int(voxel_id.GetValue(front))))
C.check(mce.probe_domain_at_pixel(dual.domain_view, 1, 1) is None,
        "probe_domain_at_pixel on empty background: None")
simple.SaveScreenshot(os.path.join(out, "brush_synthetic_volume.png"), view,
                      ImageResolution=[500, 400])
simple.ClearSelection(dual.filter)
dual.stop()
simple.Delete(simple.FindSource(mce.BRUSHED_VOXELS))

# ---- (2) the real brain -----------------------------------------------------------------
t1 = simple.OpenDataFile(T.data_file("ch2.nii.gz"))
aal = simple.OpenDataFile(T.data_file("aal.nii.gz"))
brodmann = simple.OpenDataFile(T.data_file("brodmann.nii.gz"))
merged = simple.AppendAttributes(Input=[t1, aal, brodmann])
feats, reduction = mce.reduce_multichannel(merged, "Isomap", "6D", output_dimension=3, keep_features=True,
                                           ReferenceSampleSize=2000, NumberOfLandmarks=200)
reduction.UpdatePipeline()
image = reduction.GetClientSideObject().GetOutputDataObject(0)  # pvbatch: the data itself
bcoords = image.GetPointData().GetArray("ReducedCoordinates")
bfg = image.GetPointData().GetArray("Foreground")
bdims = image.GetDimensions()
brain_view = G.black_view((500, 400))
bdisplay = mce.show_gaussian_tf(reduction, brain_view)
mce.auto_widgets(bdisplay, 4)
bdual = mce.show_dual_domain(bdisplay, brain_view, sample_size=20000)
C.check(list(bdual.domain_view.Background) == list(brain_view.Background) == [0.0, 0.0, 0.0]
        and bdual.domain_view.UseColorPaletteForBackground == 0,
        "the domain view has the volume view's own background: %s"
        % list(bdual.domain_view.Background))
voxel = (bdims[0] // 2, bdims[1] // 2, bdims[2] // 2)
vid = voxel[0] + bdims[0] * (voxel[1] + bdims[1] * voxel[2])
hit = mce.probe(bdisplay, voxel)
C.check(close(hit.coordinates, bcoords.GetTuple3(vid)) and hit.point_id == vid and
        hit.foreground == int(bfg.GetValue(vid)) and B.len(hit.features) == 6 and
        B.len(hit.channels) == 3,
        "brain: probe %s -> its ReducedCoordinates %s, 6 features, 3 channels, Foreground %d"
        % (voxel, ["%.3f" % v for v in hit.coordinates], hit.foreground))
C.check(close(simple.FindSource(mce.PROBE_MARKER).Center, hit.coordinates),
        "brain: the marker at those coordinates in the domain view")
bcloud = servermanager.Fetch(bdual.filter)
bvoxel = bcloud.GetPointData().GetArray("VoxelId")
# A box around the probed voxel's coordinates, a tenth of each coordinate's range wide.
bbox = []
for a in range(3):
    lo_a, hi_a = bcoords.GetRange(a)
    bbox += [hit.coordinates[a] - 0.1 * (hi_a - lo_a), hit.coordinates[a] + 0.1 * (hi_a - lo_a)]
expected_brain = B.set()
for p in range(bcloud.GetNumberOfPoints()):
    v = int(bvoxel.GetValue(p))
    c = bcoords.GetTuple3(v)  # the volume's own array, at the point's voxel
    if all(bbox[2 * a] <= c[a] <= bbox[2 * a + 1] for a in range(3)):
        expected_brain.add(v)
count = mce.brush(bdisplay, box=bbox)
C.check(len(expected_brain) > 0 and count == len(expected_brain) and
        highlighted_ids() == expected_brain,
        "brain: brush(box) highlights the %d sampled voxels whose coordinates lie in the box "
        "(%d)" % (len(expected_brain), count))
simple.ResetCamera(brain_view)
simple.Render(brain_view)
simple.SaveScreenshot(os.path.join(out, "probe_brush_brain.png"), brain_view,
                      ImageResolution=[500, 400])
simple.SaveScreenshot(os.path.join(out, "probe_brush_brain_domain.png"), bdual.domain_view,
                      ImageResolution=[400, 400])
C.finish()
