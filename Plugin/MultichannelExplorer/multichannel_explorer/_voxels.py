"""Private helpers of probing and brushing: the volume's grid (extent, origin, spacing,
direction), voxel index <-> point id <-> world position, one voxel's values read on the
server side, and the views that show a source.

Voxel indices (i, j, k) count from the first voxel of the volume's whole extent
(0-based), so that the point id is i + nx (j + ny k) over the WHOLE volume: the VoxelId of
ReducedDomain. Voxels are read through the plugin's ExtractVoxels filter, which takes
such global ids and outputs each voxel once from the process that owns it, so the same id
names the same voxel in a serial session, under mpiexec pvbatch and on an MPI pvserver
(a one-voxel Extract Subset fetched under MPI comes back empty unless the first process
holds the voxel, and ID selections count ids within each process's piece).
"""

from ._common import (_check_server_alive, _check_server_plugin, _coordinate_tuple, _is_float16,
                      _remote_hint, _same_proxy, _simple, _view_time)

# Point arrays of the volume that are not channels (ModelDistance: an applied model's
# distances; VoxelId and VoxelIJK: ExtractVoxels').
_NOT_CHANNELS = ("Features", "ReducedCoordinates", "Foreground", "ModelDistance",
                 "vtkGhostType", "vtkValidPointMask", "VoxelId", "VoxelIJK")


# The last grids read, by (proxy, extent, bounds): a probe reads the grid once, not at
# every click (the one-voxel read-back is a server round trip).
_GRIDS = {}


class _Grid(object):
    """The volume's whole extent and its index -> world transform (origin, spacing,
    direction), read from a one-voxel extract so that nothing large is fetched, and kept
    while the volume's extent and bounds stay the same."""

    def __init__(self, source):
        source.UpdatePipeline(_view_time())  # the time step on screen
        _check_server_alive()  # a server lost during the update leaves no extent
        info = source.GetDataInformation()
        extent = [int(v) for v in info.GetExtent()]
        if extent[1] < extent[0] or extent[3] < extent[2] or extent[5] < extent[4]:
            raise ValueError("probe/brush need image data (a volume with an extent); %s has "
                             "none%s" % (source.SMProxy.GetXMLLabel(), _remote_hint()))
        self.source = source
        self.extent = extent
        self.dims = [extent[2 * a + 1] - extent[2 * a] + 1 for a in range(3)]
        key = (source.SMProxy.GetGlobalID(), getattr(source, "Port", 0), tuple(extent),
               tuple(float(v) for v in info.GetBounds()))
        known = _GRIDS.get(key)
        if known is not None:
            self.origin, self.spacing, self.direction = known
            return
        corner = _fetch_voxels(source, [0])
        fd = corner.GetFieldData()
        arrays = [fd.GetArray(n) for n in ("Origin", "Spacing", "Direction")]
        if any(a is None for a in arrays):
            raise RuntimeError("ExtractVoxels returned no grid (Origin, Spacing, Direction) "
                               "for %s" % source.SMProxy.GetXMLLabel())
        origin, spacing, direction = [[a.GetValue(v) for v in range(a.GetNumberOfTuples())]
                                      for a in arrays]
        self.origin = origin
        self.spacing = spacing
        self.direction = [direction[3 * r:3 * r + 3] for r in range(3)]
        if len(_GRIDS) > 16:
            _GRIDS.clear()
        _GRIDS[key] = (self.origin, self.spacing, self.direction)

    def point_id(self, index):
        i, j, k = index
        return i + self.dims[0] * (j + self.dims[1] * k)

    def index_of_id(self, point_id):
        point_id = int(point_id)
        if not 0 <= point_id < self.dims[0] * self.dims[1] * self.dims[2]:
            raise ValueError("point id %d outside the volume's %d voxels"
                             % (point_id, self.dims[0] * self.dims[1] * self.dims[2]))
        nxy = self.dims[0] * self.dims[1]
        return [point_id % self.dims[0], (point_id % nxy) // self.dims[0], point_id // nxy]

    def check_index(self, index):
        index = [int(v) for v in index]
        if any(not 0 <= index[a] < self.dims[a] for a in range(3)):
            raise ValueError("voxel index %s outside the volume (dimensions %s)"
                             % (tuple(index), tuple(self.dims)))
        return index

    def position(self, index):
        """World position of a voxel: origin + direction (spacing * absolute index)."""
        scaled = [(index[a] + self.extent[2 * a]) * self.spacing[a] for a in range(3)]
        return [self.origin[r] + sum(self.direction[r][c] * scaled[c] for c in range(3))
                for r in range(3)]

    def continuous_index(self, position):
        """(0-based) continuous voxel index of a world position; the direction matrix is
        orthonormal, so its inverse is its transpose."""
        d = [position[r] - self.origin[r] for r in range(3)]
        local = [sum(self.direction[r][c] * d[r] for r in range(3)) for c in range(3)]
        return [local[a] / self.spacing[a] - self.extent[2 * a] for a in range(3)]

    def nearest_index(self, position):
        """Nearest voxel of a world position, clamped into the volume."""
        return [min(max(int(round(x)), 0), self.dims[a] - 1)
                for a, x in enumerate(self.continuous_index(position))]

    def index_at(self, position):
        """Nearest voxel of a world position inside the volume (within half a voxel of its
        outermost voxel centres); a ValueError for a position outside."""
        continuous = self.continuous_index(position)
        if any(not -0.5 <= x <= self.dims[a] - 0.5 for a, x in enumerate(continuous)):
            b = self.bounds()
            raise ValueError("position %s is outside the volume (bounds x %g..%g, y %g..%g, "
                             "z %g..%g, half a voxel around the outermost voxel centres "
                             "included)" % (tuple(float(v) for v in position), *b))
        return self.nearest_index(position)

    def bounds(self):
        corners = [self.position([i, j, k]) for i in (0, self.dims[0] - 1)
                   for j in (0, self.dims[1] - 1) for k in (0, self.dims[2] - 1)]
        return [f(p[a] for p in corners) for a in range(3) for f in (min, max)]


def _extract_voxels_proxy(source, ids):
    """An unregistered ExtractVoxels (nothing appears in the pipeline browser) of `source`
    at global voxel ids `ids`."""
    from paraview import servermanager

    _check_server_plugin()
    ctor = getattr(servermanager.filters, "ExtractVoxels", None)
    if ctor is None:
        raise RuntimeError(
            "The ExtractVoxels filter is not available: load the MultichannelExplorer plugin "
            "on the client and on the server, e.g. LoadPlugin(path, remote=False, "
            "ns=globals()) and LoadPlugin(path, remote=True, ns=globals())")
    extract = ctor(Input=source)
    extract.VoxelIds = [int(v) for v in ids]
    return extract


def _fetch_voxels(source, ids):
    """The voxels at global ids `ids` as a vtkPolyData (ExtractVoxels' output gathered
    from every process: one point per voxel, its exact values, VoxelId, VoxelIJK, and the
    volume's Origin, Spacing, Direction and WholeExtent as field data)."""
    from paraview import servermanager

    extract = _extract_voxels_proxy(source, ids)
    # Updated as a pipeline first (each process its piece): fetched straight away, the
    # reduction's request leaves the pieces of the processes other than the first empty.
    extract.UpdatePipeline(_view_time())  # the time step on screen
    return servermanager.Fetch(extract)


def _values_at(voxels, row, coordinates="ReducedCoordinates"):
    """{array name: tuple of values} of point `row` of an ExtractVoxels output."""
    pd = voxels.GetPointData()
    values = {}
    for a in range(pd.GetNumberOfArrays()):
        array = pd.GetAbstractArray(a)
        if array is None or not hasattr(array, "GetTuple") or array.GetName() is None:
            continue
        if array.GetName() in ("VoxelId", "VoxelIJK"):
            continue
        if array.GetName() == coordinates:
            values[array.GetName()] = _coordinate_tuple(array, row)
            continue
        values[array.GetName()] = tuple(float(v) for v in array.GetTuple(row))
    return values


def _voxel_values(source, grid, index, coordinates="ReducedCoordinates", fetched=None):
    """{array name: tuple of values} of one voxel (exact values, no interpolation), and
    the label tables that came with it ({channel: {value: label}}). The array named
    `coordinates` is read as reduced coordinates: float16 (unsigned-short bits) decoded;
    other unsigned-short arrays (16-bit channels) are plain numbers. `fetched`: an
    ExtractVoxels output already read back that may hold the voxel (probe_at_pixel's ray):
    no second round trip then."""
    point_id = grid.point_id(index)
    found = None
    for voxels in ([fetched] if fetched is not None else []) + [None]:
        if voxels is None:
            voxels = _fetch_voxels(source, [point_id])
        found = voxels.GetPointData().GetArray("VoxelId") if voxels is not None else None
        rows = [r for r in range(found.GetNumberOfTuples()) if found.GetValue(r) == point_id] \
            if found is not None else []
        if rows:
            return _values_at(voxels, rows[0], coordinates), label_tables(voxels)
    raise RuntimeError("voxel %s (id %d) of %s was not returned by the server (%d "
                       "points came back)" % (tuple(index), point_id,
                                              source.SMProxy.GetXMLLabel(),
                                              found.GetNumberOfTuples() if found else 0))


def _coordinate_range(source, name):
    """Per-component (min, max) of the coordinate array over the whole volume. For float16
    coordinates the ranges ParaView gathers are those of the bits: DimensionReduction's
    field array <name>Range (min and max tuples) holds the decoded ones."""
    info = source.PointData[name]
    if info is None:
        raise ValueError("%s has no point array %s" % (source.SMProxy.GetXMLLabel(), name))
    if _is_float16(info):
        decoded = source.FieldData[name + "Range"]
        if decoded is None:
            raise ValueError("%s: the float16 coordinates %s come without their range (the "
                             "field array %sRange of DimensionReduction)"
                             % (source.SMProxy.GetXMLLabel(), name, name))
        info = decoded
    return [tuple(info.GetRange(c)) for c in range(info.GetNumberOfComponents())]


def _views_showing(proxy, port=None):
    """Render views in which `proxy` (output `port`, any when None) is visible."""
    simple = _simple()
    found = []
    for view in simple.GetRenderViews():
        for rep in view.Representations:
            inp = getattr(rep, "Input", None)
            if inp is None or not _same_proxy(inp, proxy):
                continue
            if port is not None and getattr(inp, "Port", 0) != port:
                continue
            if rep.Visibility:
                found.append(view)
                break
    return found


def _find_or_create(name, factory):
    """The registered source called `name`, else factory(registrationName=name); the
    active source is left as it was (the GUI's buttons act on it)."""
    simple = _simple()
    proxy = simple.FindSource(name)
    if proxy is None:
        active = simple.GetActiveSource()
        proxy = factory(registrationName=name)
        if active is not None:
            simple.SetActiveSource(active)
    return proxy


LABEL_TABLE_SUFFIX = "_labels"  # mcvLabelTables.h: field array <channel>_labels


def label_tables(data):
    """{channel: {value: label}} from the label tables in a dataset's field data (an
    atlas's names, attached by the NIfTI reader from the label file beside the volume,
    e.g. MRIcron's aal.nii.txt; entries "<value>\\t<name>"). ExtractVoxels passes them
    on, so the probe's fetch brings them."""
    tables = {}
    fd = data.GetFieldData() if data is not None else None
    for a in range(fd.GetNumberOfArrays() if fd is not None else 0):
        array = fd.GetAbstractArray(a)
        name = array.GetName() if array is not None else None
        if not name or not name.endswith(LABEL_TABLE_SUFFIX) or not hasattr(array, "GetValue"):
            continue
        table = {}
        for v in range(array.GetNumberOfValues()):
            value, _, label = str(array.GetValue(v)).partition("\t")
            try:
                table[int(value)] = label
            except ValueError:
                continue
        tables[name[:-len(LABEL_TABLE_SUFFIX)]] = table
    return tables
