"""The exploration loop gives the same answers on ParaView's distributed engine as in one
process: probing, brushing and the dual domain address voxels by GLOBAL voxel id.

Run as
  pvpython client_server_loop_check.py --reference DIR
      a built-in session: the chain on the real brain (ch2 + AAL + Brodmann, every 3rd
      voxel: 61 x 73 x 61), PCA 6D -> 3D, widgets by k-means, the picture, the best view,
      probes at voxels on every piece of a 2-, 3- and 4-process split and on the piece
      boundaries (by index, point id and world position), brush by ids, by a box and by a
      selection of the domain cloud, the dual domain's sample, add_widget_at, a probe
      through a pixel, and the errors of bad input. Each probe is also checked against the
      fetched volume itself (the voxel's own values at that global id). Writes DIR/answers.json
      and DIR/picture.png.
  pvpython client_server_loop_check.py --compare DIR --connect PORT
      the same, connected to a pvserver (e.g. mpiexec -n 2 pvserver) on localhost:PORT
      (the plugin loaded on both sides), compared answer by answer with DIR's: equal
      (coordinates within float tolerance; the picture within a small pixel tolerance).
  mpiexec -n N pvbatch --mpi client_server_loop_check.py --compare DIR
      the same under pvbatch's parallel engine.
Driver: test_client_server.sh.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402

SUBSAMPLE = 3
REDUCTION = dict(ReferenceSampleSize=3000, RandomSeed=7)
VIEW_SIZE = [400, 400]
DIFFERING_FRACTION = 0.005  # at most this fraction of the pixels may differ
COORD_TOLERANCE = 2e-4


def parse():
    parser, mode = T.reference_compare_parser()
    mode.add_argument("--no-server-plugin", action="store_true",
                      help="with --connect: the plugin loaded on the client only")
    mode.add_argument("--server-dies", metavar="MARKER",
                      help="with --connect: writes MARKER, then updates a long reduction "
                           "during which the driver kills a server process")
    parser.add_argument("--connect", type=int, metavar="PORT")
    parser.add_argument("--processes", type=int, metavar="N",
                        help="with --compare: the number of processes expected")
    return parser.parse_args()


def server_dies(port, marker):
    """A server process killed during an update: the update returns (nothing hangs) and
    probe and brush then name the lost connection as the cause of the empty volume."""
    import time

    C = T.Checker("client_server_loop_check (server killed during an update)")
    mce = connect_and_load(port)
    channels = [simple.OpenDataFile(T.data_file(n))
                for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
    feats, red = mce.reduce_multichannel(simple.AppendAttributes(Input=channels), "Isomap",
                                         "24D", ReferenceSampleSize=8000)
    with open(marker, "w") as f:
        f.write("updating\n")
    start = time.time()
    red.UpdatePipeline()  # the driver kills a server process meanwhile
    took = time.time() - start
    C.check(took < 250, "the update returned %.1f s after it started" % took)
    for name, call in (("probe", lambda: mce.probe(red, (0, 0, 0), mark=False)),
                       ("brush", lambda: mce.brush(red, voxel_ids=[0]))):
        try:
            call()
            message = None
        except (RuntimeError, ValueError) as error:
            message = str(error)
        C.check(message is not None and "lost connection to the pvserver" in message,
                "%s after the server died: %s" % (name, message))
    C.finish()


def without_server_plugin(port):
    """The plugin on the client only: the helpers refuse with an error that names what is
    missing, instead of failing on the server or returning nothing."""
    C = T.Checker("client_server_loop_check (server without the plugin)")
    if simple.Connect("localhost", port) is None:
        print("FAIL: could not connect to a pvserver on localhost:%d" % port)
        sys.stdout.flush()
        os._exit(1)
    simple.LoadPlugin(os.environ["MCV_PLUGIN"], remote=False)
    import multichannel_explorer as mce

    wavelet = simple.Wavelet()
    for name, call in (("reduce_multichannel", lambda: mce.reduce_multichannel(wavelet, "PCA", "6D")),
                       ("probe", lambda: mce.probe(wavelet, (0, 0, 0), mark=False)),
                       ("brush", lambda: mce.brush(wavelet, voxel_ids=[0]))):
        try:
            call()
            message = None
        except RuntimeError as error:
            message = str(error)
        C.check(message is not None and "not loaded on the server" in message and
                "remote=True" in message, "%s: %s" % (name, message))
    simple.Disconnect()
    C.finish()


def connect_and_load(port):
    """Connects to localhost:PORT and loads the plugin on the server and the client."""
    plugin = os.environ.get("MCV_PLUGIN")
    if not plugin:
        print("FAIL: MCV_PLUGIN is not set")
        sys.stdout.flush()
        os._exit(1)
    connection = simple.Connect("localhost", port)
    if connection is None:
        print("FAIL: could not connect to a pvserver on localhost:%d" % port)
        sys.stdout.flush()
        os._exit(1)
    simple.LoadPlugin(plugin, remote=True)
    simple.LoadPlugin(plugin, remote=False)
    import multichannel_explorer

    return multichannel_explorer


def piece_extents(whole, pieces):
    """The extents ParaView's block split gives `pieces` processes (vtkExtentTranslator)."""
    from vtkmodules.vtkCommonExecutionModel import vtkExtentTranslator

    translator = vtkExtentTranslator()
    out = []
    for p in range(pieces):
        ext = [0] * 6
        translator.PieceToExtentThreadSafe(p, pieces, 0, whole, ext,
                                           vtkExtentTranslator.BLOCK_MODE, 0)
        out.append(ext)
    return out


def probed_voxels(dims):
    """Voxels (0-based indices) on every piece of 2-, 3- and 4-process splits and on both
    sides of each piece boundary, plus the corners and the centre."""
    whole = [0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1]
    voxels = set()
    for corner in [(i, j, k) for i in (0, dims[0] - 1) for j in (0, dims[1] - 1)
                   for k in (0, dims[2] - 1)]:
        voxels.add(corner)
    voxels.add(tuple(d // 2 for d in dims))
    for pieces in (2, 3, 4):
        for ext in piece_extents(whole, pieces):
            centre = [(ext[2 * a] + ext[2 * a + 1]) // 2 for a in range(3)]
            voxels.add(tuple(centre))
            for a in range(3):
                for v in (ext[2 * a] - 1, ext[2 * a], ext[2 * a + 1], ext[2 * a + 1] + 1):
                    if 0 <= v < dims[a]:
                        p = list(centre)
                        p[a] = v
                        voxels.add(tuple(p))
    return sorted(voxels)


def probe_record(hit):
    return dict(index=list(hit.index), point_id=hit.point_id,
                position=[float(v) for v in hit.position],
                coordinates=[float(v) for v in hit.coordinates],
                channels={k: float(v) for k, v in hit.channels.items()},
                foreground=hit.foreground)


def brushed(mce):
    """(VoxelIds, world positions) of what brush() shows (BrushedVoxels' output)."""
    data = servermanager.Fetch(simple.FindSource(mce.BRUSHED_VOXELS))
    ids = data.GetPointData().GetArray("VoxelId")
    pairs = sorted((int(ids.GetValue(p)), list(data.GetPoint(p)))
                   for p in range(data.GetNumberOfPoints())) if ids else []
    return [p[0] for p in pairs], [p[1] for p in pairs]


def error_of(call):
    try:
        call()
    except ValueError as error:
        return str(error)
    return None


def stage(name):
    """Progress on stdout (where a run that stops shows how far it got)."""
    print("-- %s" % name)
    sys.stdout.flush()


def run(mce, out, reference, previous=None):
    answers = {}
    stage("chain")
    volume = T.brain_subset(SUBSAMPLE)
    feats, red = mce.reduce_multichannel(volume, "PCA", "6D", output_dimension=3, **REDUCTION)
    red.UpdatePipeline()
    ext = red.GetDataInformation().GetExtent()
    dims = [ext[2 * a + 1] - ext[2 * a] + 1 for a in range(3)]
    answers["dims"] = dims
    ranges = red.PointData["ReducedCoordinates"]
    answers["coordinate_ranges"] = [list(ranges.GetRange(c)) for c in range(3)]

    view = T.render_view(VIEW_SIZE)
    stage("widgets and best view")
    display = mce.show_gaussian_tf(red, view)
    answers["widgets"] = [float(v) for v in mce.auto_widgets(display, 3, seed=1)]
    # Named from the sample and its voxels' neighbours (ExtractVoxels on every process).
    answers["widget_names"] = [str(n) for n in display.GaussianWidgetNames]
    best = mce.apply_best_viewpoint(red, view)
    answers["best_view"] = [float(v) for v in best.direction]
    # A shown widget hidden by its name (edit_widget), the best view of what is left, and
    # the widget shown again (the picture and what follows as before).
    shown = [n for i, n in enumerate(answers["widget_names"]) if answers["widgets"][8 * i + 7] > 0]
    mce.edit_widget(display, shown[0], shown=False)
    answers["edited_widgets"] = [float(v) for v in display.GaussianWidgets]
    answers["edited_best_view"] = [float(v) for v in mce.apply_best_viewpoint(red, view).direction]
    mce.edit_widget(display, shown[0], shown=True)
    # The Best View button's call: each side's entropy from its screenshot (no render of
    # its own before it), the kept side shown; its picture must have the winning entropy.
    sided = mce.apply_best_viewpoint(red, view, disambiguate=True)
    final = os.path.join(out, "disambiguated.png" if reference else "disambiguated_compare.png")
    simple.SaveScreenshot(final, view)
    answers["disambiguated"] = dict(sign=sided.sign, entropies=sided.entropies,
                                    final_entropy=mce.image_entropy(final))
    mce.apply_best_viewpoint(red, view)
    stage("picture")
    picture = os.path.join(out, "picture.png" if reference else "picture_compare.png")
    # The volume is compared; the widget legend's rows differ (a client of a remote render
    # server has no voxels to count the shares on, docs/client-server.md): it is checked by
    # client_server_legend_check.py.
    display.ShowWidgetLegend = 0
    simple.Render(view)
    simple.SaveScreenshot(picture, view, ImageResolution=VIEW_SIZE)
    # Whether the render server could render (ParaView asks every server process for
    # OpenGL through its display when the view is made): without it the client draws the
    # view itself, and a volume, which stays on the server, is missing from the picture.
    answers["remote_rendering_available"] = bool(
        view.GetClientSideObject().GetRemoteRenderingAvailable())

    stage("probes")
    # Probes by index at every piece and boundary, a few by point id and world position.
    voxels = probed_voxels(dims)
    answers["probes"] = [probe_record(mce.probe(display, v, mark=False)) for v in voxels]
    sample = voxels[::7]
    answers["probes_by_id"] = [
        probe_record(mce.probe(display, v[0] + dims[0] * (v[1] + dims[1] * v[2]), mark=False))
        for v in sample]
    answers["probes_by_position"] = [
        probe_record(mce.probe(display, position=[c + 0.2 for c in p["position"]], mark=False))
        for p in answers["probes"][::7]]

    stage("dual domain")
    # The dual domain: its sample and a probe with the markers.
    dual = mce.show_dual_domain(display, view, sample_size=4000)
    cloud = servermanager.Fetch(dual.filter)
    cloud_ids = cloud.GetPointData().GetArray("VoxelId")
    answers["domain_ids"] = [int(cloud_ids.GetValue(p)) for p in range(cloud.GetNumberOfPoints())]
    answers["domain_points"] = [list(cloud.GetPoint(p)) for p in range(0, cloud.GetNumberOfPoints(), 97)]
    # the domain view framed on FocusBounds (piece 0's field data, read through the client)
    answers["domain_focus"] = [float(v) for v in dual.domain_view.CameraFocalPoint]
    marked = mce.probe(display, voxels[len(voxels) // 2])
    marker = simple.FindSource(mce.PROBE_MARKER)
    answers["probe_marker"] = [float(v) for v in marker.Center] if marker else None
    voxel_marker = simple.FindSource("ProbeVoxelMarker")
    answers["probe_voxel_marker"] = [float(v) for v in voxel_marker.Center] if voxel_marker else None
    answers["added_widget"] = [float(v) for v in mce.add_widget_at(display, marked)]
    # The voxel of the domain cloud's point seen at a pixel of the domain view (the pixel
    # of cloud point 123, projected in the built-in run).
    dual.domain_view.ViewSize = VIEW_SIZE
    simple.Render(dual.domain_view)
    if previous is None:
        import gaussian_tf_testing as G

        answers["domain_pixel"] = list(G.project(dual.domain_view, cloud.GetPoint(123)))
    else:
        answers["domain_pixel"] = previous["domain_pixel"]
    hit = mce.probe_domain_at_pixel(dual.domain_view, *answers["domain_pixel"])
    answers["probe_domain_at_pixel"] = probe_record(hit) if hit is not None else None

    stage("brushing")
    # Brushing: ids on every piece and its boundaries, a box, a selection of the cloud.
    ids = sorted(set(p["point_id"] for p in answers["probes"]))
    answers["brush_ids_count"] = mce.brush(display, voxel_ids=ids)
    answers["brush_ids"], answers["brush_ids_positions"] = brushed(mce)
    lo = answers["coordinate_ranges"]
    box = []
    for a in range(3):
        span = lo[a][1] - lo[a][0]
        box += [lo[a][0] + 0.45 * span, lo[a][0] + 0.6 * span]
    answers["brush_box_count"] = mce.brush(display, box=box)
    answers["brush_box"], positions = brushed(mce)
    display.Visibility = 0  # the brushed voxels alone (the volume would hide them)
    simple.SaveScreenshot(os.path.join(out, "brush_box%s.png" % ("" if reference else "_compare")),
                          view, ImageResolution=VIEW_SIZE)
    display.Visibility = 1
    answers["brush_box_positions"] = positions[::11]
    chosen = [3, 10, 50, 333]
    simple.SelectIDs(IDs=[v for c in chosen for v in (0, c)], FieldType="POINT",
                     Source=dual.filter)
    answers["brush_selection_count"] = mce.brush(dual.filter)
    answers["brush_selection"], _ = brushed(mce)
    simple.ClearSelection(dual.filter)

    stage("probe_at_pixel")
    # The voxel through the middle pixel of the volume view.
    hit = mce.probe_at_pixel(view, VIEW_SIZE[0] // 2, VIEW_SIZE[1] // 2)
    answers["probe_at_pixel"] = list(hit.index) if hit is not None else None

    stage("bad input")
    # Bad input: errors, not answers.
    n = dims[0] * dims[1] * dims[2]
    answers["errors"] = {
        "probe index outside": error_of(lambda: mce.probe(display, (dims[0], 0, 0))),
        "probe id outside": error_of(lambda: mce.probe(display, n)),
        "probe position outside": error_of(lambda: mce.probe(
            display, position=[b + 1000.0 for b in answers["probes"][0]["position"]])),
        "brush id outside": error_of(lambda: mce.brush(display, voxel_ids=[0, n])),
        "brush negative id": error_of(lambda: mce.brush(display, voxel_ids=[-1])),
    }
    stage("ExtractVoxels")
    # ExtractVoxels itself: an id outside the volume is the filter's error (nothing out);
    # a repeated id comes out as often as listed; voxels of every piece in one list.
    extract = servermanager.filters.ExtractVoxels(Input=red)
    extract.VoxelIds = [0, n]
    extract.UpdatePipeline()
    answers["extract_outside_points"] = servermanager.Fetch(extract).GetNumberOfPoints()
    extract.VoxelIds = [ids[-1], 5, ids[-1]] + ids[:3]
    extract.UpdatePipeline()
    data = servermanager.Fetch(extract)
    got = data.GetPointData().GetArray("VoxelId")
    answers["extract_listed"] = sorted(int(got.GetValue(p)) for p in range(got.GetNumberOfTuples()))
    ijk = data.GetPointData().GetArray("VoxelIJK")
    answers["extract_ijk_match"] = all(
        list(ijk.GetTuple3(p)) == [v % dims[0], (v // dims[0]) % dims[1], v // (dims[0] * dims[1])]
        for p, v in ((p, int(got.GetValue(p))) for p in range(got.GetNumberOfTuples())))
    # State: saved with the brushed voxels, loaded back (beside what is there): the loaded
    # BrushedVoxels draws the same voxels.
    stage("state")
    state = os.path.join(out, "loop_state%s.pvsm" % ("" if reference else "_compare"))
    simple.SaveState(state)
    before = set(simple.GetSources().keys())
    simple.LoadState(state)
    loaded = [proxy for key, proxy in simple.GetSources().items()
              if key not in before and key[0] == mce.BRUSHED_VOXELS]
    answers["state_brush"] = None
    if len(loaded) == 1:
        # Updated on its own, first: the loaded chain was never updated before.
        loaded[0].UpdatePipeline()
        data = servermanager.Fetch(loaded[0])
        got = data.GetPointData().GetArray("VoxelId")
        answers["state_brush"] = sorted(int(got.GetValue(p))
                                        for p in range(got.GetNumberOfTuples())) if got else []
    dual.stop()

    # A transfer-function file: saved (the fitted model written beside it by the server's
    # processes), the widgets changed, loaded back (the reduction then applies the model).
    stage("transfer function file")
    tf = os.path.join(out, "loop%s.mcvtf" % ("" if reference else "_compare"))
    for old in (tf, tf[:-len(".mcvtf")] + ".mcvmodel"):
        if os.path.exists(old):
            os.remove(old)
    mce.save_transfer_function(display, tf)
    saved = [float(v) for v in display.GaussianWidgets]
    display.GaussianWidgets = saved[:8]
    mce.load_transfer_function(display, tf)
    model = tf[:-len(".mcvtf")] + ".mcvmodel"
    red.UpdatePipeline()
    ranges = red.PointData["ReducedCoordinates"]
    answers["tf_file"] = {
        "saved_widgets": saved,
        "loaded_widgets": [float(v) for v in display.GaussianWidgets],
        "model_file": os.path.basename(str(red.ModelFile)),
        "model_sha256": file_digest(model),
        "model_size": os.path.getsize(model) if os.path.exists(model) else None,
        # The header (channels, normalisation, method, fit): the z-score scales are sums
        # over the processes' pieces, equal to about 1e-13, not bit for bit (and the file
        # may be a byte longer or shorter for a digit more or less).
        "model_header": {k: v for k, v in mce.read_model(model).items() if k != "crc32"}
        if os.path.exists(model) else None,
        "ranges_with_model": [list(ranges.GetRange(c)) for c in range(3)],
    }
    return answers, picture, red


def file_digest(path):
    """sha256 of a file's bytes, None when it does not exist."""
    import hashlib

    if not os.path.exists(path):
        return None
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def ground_truth_checks(C, answers, red):
    """Built-in session: each probe returned the voxel at its global id (the fetched
    volume's own values), and each brushed point sits at its voxel."""
    image = servermanager.Fetch(red)
    pd = image.GetPointData()
    coords = pd.GetArray("ReducedCoordinates")
    channels = {name: pd.GetArray(name) for name in T.BRAIN}
    wrong = []
    for p in answers["probes"] + answers["probes_by_id"] + answers["probes_by_position"]:
        pid = p["point_id"]
        i, j, k = p["index"]
        d = answers["dims"]
        ok = (pid == i + d[0] * (j + d[1] * k) and
              all(abs(a - b) <= 1e-6 for a, b in zip(p["position"], image.GetPoint(pid))) and
              list(coords.GetTuple3(pid)) == p["coordinates"] and
              all(channels[c].GetTuple1(pid) == p["channels"][c] for c in T.BRAIN))
        if not ok:
            wrong.append(p["index"])
    C.check(not wrong, "built-in: %d probes return the voxel at their global id (its own "
            "coordinates, channels and position; wrong: %s)"
            % (len(answers["probes"]) + len(answers["probes_by_id"]) +
               len(answers["probes_by_position"]), wrong[:5]))
    misplaced = [v for v, x in zip(answers["brush_ids"], answers["brush_ids_positions"])
                 if any(abs(a - b) > 1e-6 for a, b in zip(x, image.GetPoint(v)))]
    C.check(answers["brush_ids"] and not misplaced,
            "built-in: every brushed voxel is drawn at its own position (%d)"
            % len(answers["brush_ids"]))


def compare(C, reference, answers, ref_picture, picture, processes):
    """Each answer equal to the built-in one: a table row per check, [(name, ok, detail)]."""
    rows = []

    def row(name, ok, detail=""):
        C.check(ok, "%-26s built-in vs %d process(es): %s %s"
                % (name, processes, "equal" if ok else "DIFFERENT", detail))
        rows.append((name, ok, detail))

    row("chain (extent)", answers["dims"] == reference["dims"], str(answers["dims"]))
    row("coordinate ranges", T.close(answers["coordinate_ranges"], reference["coordinate_ranges"],
                                   COORD_TOLERANCE))
    row("auto widgets", T.close(answers["widgets"], reference["widgets"], 1e-3))
    row("widget names", answers["widget_names"] == reference["widget_names"],
        str(answers["widget_names"]))
    row("best view", T.close(answers["best_view"], reference["best_view"], 1e-3),
        str(["%.4f" % v for v in answers["best_view"]]))
    row("edit_widget, its best view",
        T.close(answers["edited_widgets"], reference["edited_widgets"], 1e-3) and
        T.close(answers["edited_best_view"], reference["edited_best_view"], 1e-3),
        str(["%.4f" % v for v in answers["edited_best_view"]]))
    sided, ref_sided = answers["disambiguated"], reference["disambiguated"]
    row("best view, disambiguated",
        sided["sign"] == ref_sided["sign"] and
        abs(sided["final_entropy"] - max(sided["entropies"].values())) < 0.05,
        "sign %+d (built-in %+d), entropies %s, its picture's %.3f"
        % (sided["sign"], ref_sided["sign"],
           {k: round(v, 3) for k, v in sorted(sided["entropies"].items())},
           sided["final_entropy"]))
    diff = T.picture_difference(ref_picture, picture)
    why = ""
    if answers.get("remote_rendering_available") is False:
        why = ("; the render server could not render (no OpenGL through its display: "
               "remote rendering not available), so the client drew the view without the "
               "volume")
    elif T.blank_picture(picture):
        why = "; the picture is blank (background only)"
    row("picture", diff is not None and diff[1] <= DIFFERING_FRACTION,
        "max channel difference %s, %.3f%% of pixels above %d%s"
        % (diff and diff[0], 100 * diff[1] if diff else 100, T.PIXEL_TOLERANCE, why))
    for key in ("probes", "probes_by_id", "probes_by_position"):
        bad = [r["index"] for r, a in zip(reference[key], answers[key])
               if not T.close(a, r, COORD_TOLERANCE)]
        row(key, len(answers[key]) == len(reference[key]) and not bad,
            "%d voxels (differ: %s)" % (len(reference[key]), bad[:4]))
    row("domain sample (VoxelIds)", answers["domain_ids"] == reference["domain_ids"],
        "%d points, %d distinct (built-in %d)" % (len(answers["domain_ids"]),
                                                len(set(answers["domain_ids"])),
                                                len(reference["domain_ids"])))
    row("domain framing", T.close(answers["domain_focus"], reference["domain_focus"], COORD_TOLERANCE),
        "focal point %s" % ["%.3f" % v for v in answers["domain_focus"]])
    row("domain points", T.close(answers["domain_points"], reference["domain_points"],
                               COORD_TOLERANCE))
    row("probe markers", T.close([answers["probe_marker"], answers["probe_voxel_marker"]],
                               [reference["probe_marker"], reference["probe_voxel_marker"]],
                               COORD_TOLERANCE))
    row("add_widget_at", T.close(answers["added_widget"], reference["added_widget"], 1e-3))
    row("probe_domain_at_pixel", answers["probe_domain_at_pixel"] is not None and
        T.close(answers["probe_domain_at_pixel"], reference["probe_domain_at_pixel"],
              COORD_TOLERANCE), str(answers["probe_domain_at_pixel"] and
                                    answers["probe_domain_at_pixel"]["index"]))
    for key in ("brush_ids", "brush_box", "brush_selection"):
        row(key, answers[key] == reference[key] and
            answers[key + "_count"] == reference[key + "_count"],
            "%d voxels (built-in %d)" % (len(answers[key]), len(reference[key])))
    row("brushed positions", T.close(answers["brush_ids_positions"],
                                   reference["brush_ids_positions"], 1e-9) and
        T.close(answers["brush_box_positions"], reference["brush_box_positions"], 1e-9))
    row("probe_at_pixel", answers["probe_at_pixel"] == reference["probe_at_pixel"],
        str(answers["probe_at_pixel"]))
    row("ExtractVoxels", answers["extract_outside_points"] == 0 and answers["extract_ijk_match"]
        and answers["extract_listed"] == reference["extract_listed"],
        "id outside: %d points; %d listed ids out" % (answers["extract_outside_points"],
                                                      len(answers["extract_listed"])))
    row("state save/load", answers["state_brush"] == answers["brush_selection"] ==
        reference["state_brush"], "the loaded BrushedVoxels: %s" % answers["state_brush"])
    row("bad input errors", answers["errors"] == reference["errors"] and
        all(answers["errors"].values()))
    tf, ref_tf = answers["tf_file"], reference["tf_file"]
    row("transfer-function file", tf["loaded_widgets"] == tf["saved_widgets"] and
        T.close(tf["saved_widgets"], ref_tf["saved_widgets"], 1e-3) and
        tf["model_header"] is not None and
        T.close(tf["model_header"], ref_tf["model_header"], 1e-9) and
        T.close(tf["ranges_with_model"], ref_tf["ranges_with_model"], COORD_TOLERANCE),
        "saved, changed, loaded back: %d widgets; %s's header equal within 1e-9 (%s bit "
        "for bit), the coordinates it gives equal"
        % (len(tf["loaded_widgets"]) // 8, tf["model_file"],
           "also" if tf["model_sha256"] == ref_tf["model_sha256"] else "not"))
    return rows


def main():
    args = parse()
    if args.no_server_plugin:
        without_server_plugin(args.connect)
    if args.server_dies:
        server_dies(args.connect, args.server_dies)
    if args.connect:
        mce = connect_and_load(args.connect)
    else:
        mce = T.load_plugin(globals())
    pm = servermanager.vtkProcessModule.GetProcessModule()
    processes = (servermanager.ActiveConnection.GetNumberOfDataPartitions()
                 if args.connect else pm.GetNumberOfLocalPartitions())
    C = T.Checker("client_server_loop_check (%s, %d process(es))"
                  % ("pvserver" if args.connect else "built-in/pvbatch", processes))
    out = args.reference or args.compare
    os.makedirs(out, exist_ok=True)
    previous = None
    if args.compare:
        with open(os.path.join(out, "answers.json")) as f:
            previous = json.load(f)
    answers, picture, red = run(mce, out, bool(args.reference), previous)
    for name, message in sorted(answers["errors"].items()):
        C.check(bool(message), "%s: %s" % (name, message))
    if args.reference:
        ground_truth_checks(C, answers, red)
        sided = answers["disambiguated"]
        C.check(abs(sided["final_entropy"] - max(sided["entropies"].values())) < 0.05,
                "built-in: the disambiguated best view shows the side of higher entropy "
                "(%s, its picture's %.3f)" % (sided["entropies"], sided["final_entropy"]))
        C.check(not T.blank_picture(picture), "built-in: the picture shows the volume (%s)"
                % picture)
        listed = sorted([answers["brush_ids"][-1], 5, answers["brush_ids"][-1]] +
                        answers["brush_ids"][:3])
        C.check(answers["extract_outside_points"] == 0 and answers["extract_ijk_match"] and
                answers["extract_listed"] == listed,
                "built-in: ExtractVoxels of an id outside: nothing; of 6 listed ids (one "
                "twice): those 6 (%s), VoxelIJK of each id" % answers["extract_listed"])
        tf = answers["tf_file"]
        C.check(tf["loaded_widgets"] == tf["saved_widgets"] and len(tf["saved_widgets"]) == 32
                and tf["model_sha256"] is not None and tf["model_file"] == "loop.mcvmodel",
                "built-in: a transfer-function file saved, the widgets changed, loaded back: "
                "the 4 widgets (3 seeded, 1 added), the reduction applies the model written "
                "beside it (%s)" % tf["model_file"])
        C.check(T.close(tf["ranges_with_model"], answers["coordinate_ranges"], COORD_TOLERANCE),
                "built-in: the model applied gives the fitted coordinate ranges %s"
                % tf["ranges_with_model"])
        C.check(answers["state_brush"] == answers["brush_selection"],
                "built-in: a saved state loaded back has BrushedVoxels with the brushed voxels "
                "%s (got %s)" % (answers["brush_selection"], answers["state_brush"]))
        hit = answers["probe_domain_at_pixel"]
        C.check(hit is not None and hit["point_id"] in answers["domain_ids"],
                "built-in: probe_domain_at_pixel at the pixel of cloud point 123 (voxel %s): "
                "the voxel of a cloud point there (%s)"
                % (answers["domain_ids"][123], hit and hit["point_id"]))
        C.check(len(answers["probes"]) >= 40 and answers["probe_at_pixel"] is not None and
                answers["brush_box_count"] > 10 and answers["brush_selection_count"] == 4 and
                len(set(answers["domain_ids"])) == len(answers["domain_ids"]) == 4000,
                "built-in: %d probes, a probe through the middle pixel, %d voxels in the box, "
                "4 selected, a domain of 4000 distinct voxels"
                % (len(answers["probes"]), answers["brush_box_count"]))
        with open(os.path.join(out, "answers.json"), "w") as f:
            json.dump(answers, f)
    else:
        reference = previous
        C.check(args.processes is None or processes == args.processes,
                "the %s runs %d process(es) (expected %s)"
                % ("server" if args.connect else "pvbatch", processes, args.processes))
        rows = compare(C, reference, answers, os.path.join(out, "picture.png"), picture,
                       processes)
        label = "%s_%d" % ("pvserver" if args.connect else "pvbatch", processes)
        with open(os.path.join(out, "answers_%s.json" % label), "w") as f:
            json.dump(answers, f)
        with open(os.path.join(out, "rows_%s.json" % label), "w") as f:
            json.dump(rows, f)
    if args.connect:
        simple.Disconnect()
    if args.compare and not args.connect:
        C.finish_parallel()  # mpiexec pvbatch: pvbatch ends the other processes
    else:
        C.finish()


if __name__ == "__main__":
    main()
