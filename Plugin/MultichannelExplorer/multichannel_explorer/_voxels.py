"""Private helpers of probing and brushing: the volume's grid (extent, origin, spacing,
direction), voxel index <-> point id <-> world position, one voxel's values read on the
server side, and the views that show a source.

Voxel indices (i, j, k) count from the first voxel of the volume's extent (0-based), so
that the point id is i + nx (j + ny k): the VoxelId of ReducedDomain.
"""

from ._common import _coordinate_tuple, _is_float16, _same_proxy, _simple

# Point arrays of the volume that are not channels.
_NOT_CHANNELS = ("Features", "ReducedCoordinates", "Foreground", "vtkGhostType",
                 "vtkValidPointMask")


class _Grid(object):
    """The volume's whole extent and its index -> world transform (origin, spacing,
    direction), read from a one-voxel extract so that nothing large is fetched."""

    def __init__(self, source):
        source.UpdatePipeline()
        extent = [int(v) for v in source.GetDataInformation().GetExtent()]
        if extent[1] < extent[0] or extent[3] < extent[2] or extent[5] < extent[4]:
            raise ValueError("probe/brush need image data (a volume with an extent); %s has "
                             "none" % source.SMProxy.GetXMLLabel())
        self.source = source
        self.extent = extent
        self.dims = [extent[2 * a + 1] - extent[2 * a] + 1 for a in range(3)]
        corner = _fetch_voxel(source, [extent[0], extent[2], extent[4]])
        self.origin = list(corner.GetOrigin())
        self.spacing = list(corner.GetSpacing())
        m = corner.GetDirectionMatrix()
        self.direction = [[m.GetElement(r, c) for c in range(3)] for r in range(3)]

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

    def bounds(self):
        corners = [self.position([i, j, k]) for i in (0, self.dims[0] - 1)
                   for j in (0, self.dims[1] - 1) for k in (0, self.dims[2] - 1)]
        return [f(p[a] for p in corners) for a in range(3) for f in (min, max)]


def _fetch_voxel(source, absolute_index):
    """One voxel (absolute extent index) as a vtkImageData, extracted on the server by an
    unregistered Extract Subset (nothing appears in the pipeline browser)."""
    from paraview import servermanager

    i, j, k = absolute_index
    subset = servermanager.filters.ExtractSubset(Input=source)
    subset.VOI = [i, i, j, j, k, k]
    return servermanager.Fetch(subset)


def _voxel_values(source, grid, index, coordinates="ReducedCoordinates"):
    """{array name: tuple of values} of one voxel (exact values, no interpolation). The
    array named `coordinates` is read as reduced coordinates: float16 (unsigned-short
    bits) decoded; other unsigned-short arrays (16-bit channels) are plain numbers."""
    image = _fetch_voxel(source, [index[a] + grid.extent[2 * a] for a in range(3)])
    pd = image.GetPointData()
    values = {}
    for a in range(pd.GetNumberOfArrays()):
        array = pd.GetAbstractArray(a)
        if array is None or not hasattr(array, "GetTuple") or array.GetName() is None:
            continue
        if array.GetName() == coordinates:
            values[array.GetName()] = _coordinate_tuple(array, 0)
            continue
        values[array.GetName()] = tuple(float(v) for v in array.GetTuple(0))
    return values


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
