"""Brushing: points selected in the reduced domain (ParaView's selection of the
ReducedDomain cloud, explicit VoxelIds, or a box in reduced coordinates) highlighted as
the voxels they stand for in the volume view.

The highlight is the plugin's ExtractVoxels filter on the volume, given the VoxelIds
(global voxel ids: the index in the whole extent, what ReducedDomain reports) and shown
as point sprites. Each process outputs the listed voxels of its own piece, so it draws the
same voxels in a serial session, under mpiexec pvbatch and on an MPI pvserver, and nothing
is copied to the client but the ids.
"""

from ._common import (_TracedProperties, _check_server_alive, _filter, _find_filter,
                      _remote_hint, _same_proxy, _simple, _view_time)
from ._voxels import _find_or_create, _views_showing
from .transfer_function import _source_and_display

__all__ = [
    "brush",
    "BRUSHED_VOXELS",
]

BRUSHED_VOXELS = "BrushedVoxels"  # the ExtractVoxels shown in the volume view


def _box_pairs(box):
    """[(lo, hi), ...] for 2 or 3 axes, from pairs or a flat xmin, xmax, ymin, ymax[, ...]."""
    flat = [float(v) for pair in box for v in (pair if isinstance(pair, (list, tuple))
                                                 else [pair])]
    if len(flat) not in (4, 6):
        raise ValueError("a box in reduced coordinates is (xmin, xmax, ymin, ymax[, zmin, "
                         "zmax]), not %r" % (box,))
    return [tuple(sorted(flat[i:i + 2])) for i in range(0, len(flat), 2)]


def _ids_in_box(domain, box):
    """VoxelIds of the domain cloud's points inside the box (bounds included)."""
    from paraview import servermanager

    pairs = _box_pairs(box)
    domain.UpdatePipeline(_view_time())  # the time step on screen
    cloud = servermanager.Fetch(domain)
    ids = cloud.GetPointData().GetArray("VoxelId")
    found = []
    for p in range(cloud.GetNumberOfPoints()):
        x = cloud.GetPoint(p)
        if all(lo <= x[a] <= hi for a, (lo, hi) in enumerate(pairs)):
            found.append(int(ids.GetValue(p)))
    return found


def _ids_selected(domain, selection):
    """VoxelIds of the domain cloud's points in a selection source (default: the
    selection ParaView holds for the ReducedDomain, e.g. after a rubber band)."""
    from paraview import servermanager

    if selection is None:
        sm_selection = domain.SMProxy.GetSelectionInput(0)
        if sm_selection is None:
            raise ValueError("no points of the reduced domain are selected: select some "
                             "(e.g. Select Points On in the domain view) or pass voxel ids "
                             "or a box")
        selection = servermanager._getPyProxy(sm_selection)
    extract = servermanager.filters.ExtractSelection(Input=domain, Selection=selection)
    extract.UpdatePipeline(_view_time())  # the time step on screen
    picked = servermanager.Fetch(extract)
    ids = picked.GetPointData().GetArray("VoxelId") if picked is not None else None
    if ids is None:
        return []
    return [int(ids.GetValue(p)) for p in range(ids.GetNumberOfTuples())]


def _domain_and_source(target, view):
    """(ReducedDomain proxy or None, volume source, display) of a volume, its display or
    its ReducedDomain filter."""
    proxy = getattr(target, "SMProxy", None)
    if proxy is not None and proxy.GetXMLName() == "ReducedDomain":
        source = target.Input
        return target, source, _source_and_display(source, view)[1]
    source, display = _source_and_display(target, view)
    return _find_filter(source, "ReducedDomain"), source, display


def brush(target, selection=None, voxel_ids=None, box=None, view=None,
          color=(0.0, 1.0, 1.0), point_size=6):
    """Highlights in the volume view the voxels that points of the reduced domain stand
    for, and returns their number.

    `target`: the volume (or its "Gaussian TF Volume" display, or its ReducedDomain
    filter, e.g. the active source after a selection in the domain view). Which points:
    `voxel_ids` (VoxelIds: the volume's point ids), or `box` (reduced coordinates,
    (xmin, xmax, ymin, ymax[, zmin, zmax]): the ReducedDomain cloud's points inside it), or
    `selection` (a selection source such as SelectIDs / a list of VoxelIds), by default
    the selection ParaView holds for the ReducedDomain (a rubber band in the domain view).

    The voxels appear as `color` point sprites in `view` (default: the view showing the
    volume, else the active one), one ExtractVoxels named BRUSHED_VOXELS that the next
    brush replaces (its VoxelIds are the brushed ids, its output point array VoxelId
    too)::

        mce.brush(display, box=(-0.5, 0.5, 0.0, 1.0))   # voxels of that part of the domain
        mce.brush(domain)                               # after a rubber band on the cloud
    """
    simple = _simple()
    domain, source, display = _domain_and_source(target, view)
    if isinstance(selection, (list, tuple)):
        voxel_ids, selection = selection, None
    if voxel_ids is not None:
        ids = [int(v) for v in voxel_ids]
    else:
        if domain is None:
            raise ValueError("brush: no ReducedDomain filter on this volume (show_dual_domain "
                             "makes one); pass voxel_ids instead")
        ids = _ids_in_box(domain, box) if box is not None else _ids_selected(domain, selection)
    ids = sorted(set(ids))
    # The whole extent's voxel count (the number of points would count the points that
    # neighbouring pieces share twice on several processes).
    source.UpdatePipeline(_view_time(view))  # the time step on screen
    _check_server_alive()  # a server lost during the update leaves no extent
    extent = source.GetDataInformation().GetExtent()
    count = 1
    for a in range(3):
        count *= max(int(extent[2 * a + 1]) - int(extent[2 * a]) + 1, 0)
    if count == 0:
        raise ValueError("brush needs a volume with voxels; %s has none%s"
                         % (source.SMProxy.GetXMLLabel(), _remote_hint()))
    outside = [v for v in ids if not 0 <= v < count]
    if outside:  # checked here so that the highlight is kept and the message is Python's
        raise ValueError("brush: voxel ids %s outside the volume's %d voxels (ids 0 to %d)"
                         % (outside[:5], count, count - 1))

    extract = simple.FindSource(BRUSHED_VOXELS)
    if extract is not None and (extract.SMProxy.GetXMLName() != "ExtractVoxels" or
                                not _same_proxy(extract.Input, source)):
        simple.Delete(extract)  # a highlight of another volume (or of an older state)
        extract = None
    if extract is None:
        extract = _find_or_create(BRUSHED_VOXELS, lambda registrationName: _filter(
            "ExtractVoxels")(Input=source, VoxelIds=ids, registrationName=registrationName))
    with _TracedProperties(extract):  # recorded in a trace being recorded
        extract.VoxelIds = ids
    if view is None:
        views = _views_showing(source)
        view = views[0] if views else simple.GetActiveViewOrCreate("RenderView")
    rep = simple.Show(extract, view)
    rep.SetRepresentationType("Points")
    with _TracedProperties(rep):
        rep.ColorArrayName = ["POINTS", ""]  # solid colour
        rep.AmbientColor = rep.DiffuseColor = list(color)
        rep.PointSize = point_size
        rep.RenderPointsAsSpheres = 1
        rep.Visibility = 1 if ids else 0
    simple.Render(view)
    return len(ids)
