"""Picking: the voxel under a pixel of the volume view, or of the domain view (the voxel
of the domain point there), for the GUI's Probe toggle.

A volume has no surface to pick, so the pixel's ray (from the view's camera, computed
here, so it works in any session) is sampled every half voxel, interpolated from the voxels
around it, read back from the server in one round trip (only those voxels), and the
widgets' opacity is composited along it as the ray caster does; the picked voxel is the
one nearest the depth where half of the opacity seen through that pixel has accumulated.
"""

import math

from ._common import _coordinate_tuple, _view_time
from ._voxels import _Grid, _fetch_voxels, _views_showing
from .probing import probe
from .transfer_function import (GAUSSIAN_TF_REPRESENTATION, _coordinates_name,
                                _widget_values)

__all__ = [
    "pixel_ray",
    "probe_at_pixel",
    "probe_domain_at_pixel",
]


def _unit(v):
    n = math.sqrt(sum(x * x for x in v)) or 1.0
    return [x / n for x in v]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def pixel_ray(view, x, y):
    """(origin, unit direction) of the ray through display pixel (x, y) of `view`
    (origin at the bottom left, as VTK's display coordinates), from the camera
    properties: perspective (vertical view angle) or parallel projection."""
    position = [float(v) for v in view.CameraPosition]
    focal = [float(v) for v in view.CameraFocalPoint]
    forward = _unit([f - p for f, p in zip(focal, position)])
    right = _unit(_cross(forward, [float(v) for v in view.CameraViewUp]))
    up = _cross(right, forward)
    width, height = [max(int(v), 1) for v in view.ViewSize]
    # Pixel centres in normalised device coordinates [-1, 1].
    u = 2.0 * (x + 0.5) / width - 1.0
    v = 2.0 * (y + 0.5) / height - 1.0
    aspect = float(width) / height
    if int(view.CameraParallelProjection):
        scale = float(view.CameraParallelScale)
        origin = [p + u * scale * aspect * r + v * scale * w
                  for p, r, w in zip(position, right, up)]
        return origin, forward
    half = math.tan(math.radians(float(view.CameraViewAngle)) / 2.0)
    direction = _unit([f + u * half * aspect * r + v * half * w
                       for f, r, w in zip(forward, right, up)])
    return position, direction


def _clip_to_box(origin, direction, bounds):
    """(t_enter, t_exit) of the ray in the axis-aligned box, or None (slab method)."""
    t0, t1 = 0.0, float("inf")
    for a in range(3):
        lo, hi = bounds[2 * a], bounds[2 * a + 1]
        if abs(direction[a]) < 1e-12:
            if not lo <= origin[a] <= hi:
                return None
            continue
        ta, tb = sorted(((lo - origin[a]) / direction[a], (hi - origin[a]) / direction[a]))
        t0, t1 = max(t0, ta), min(t1, tb)
    return (t0, t1) if t0 <= t1 else None


def _widget_alpha(widgets, c):
    """1 - prod(1 - a_i exp(-|c - mu_i|^2 / (2 sigma_i^2))): the representation's
    opacity of reduced coordinates c. The client's copy of the core's formula
    (GaussianWidgetFormula.h); pvbatch.test_widget_formula checks that they agree."""
    keep = 1.0
    for w in range(0, len(widgets) - 7, 8):
        cx, cy, cz, s, _, _, _, a = widgets[w:w + 8]
        d2 = sum((x - m) ** 2 for x, m in zip(c, (cx, cy, cz)))
        keep *= 1.0 - min(max(a, 0.0), 1.0) * math.exp(-d2 / (2.0 * s * s))
    return 1.0 - keep


def _gaussian_tf_in(view):
    for rep in view.Representations:
        try:
            if rep.Visibility and rep.Representation == GAUSSIAN_TF_REPRESENTATION:
                return rep
        except AttributeError:
            continue
    return None


def _ray_samples(grid, origin, direction, t0, t1, nearest):
    """The ray from t0 to t1 sampled every half of the smallest spacing: for each sample
    its position and the voxels that give its value with their weights (the 8 corners of
    its cell, trilinear, as the ray caster interpolates the coordinates; or, `nearest`,
    its nearest voxel alone), and the sample step length."""
    step = 0.5 * min(grid.spacing)
    count = max(2, int(math.ceil((t1 - t0) / step)))
    samples = []
    for s in range(count + 1):
        t = t0 + (t1 - t0) * s / float(count)
        at = [o + t * d for o, d in zip(origin, direction)]
        if nearest:
            samples.append((at, [(grid.point_id(grid.nearest_index(at)), 1.0)]))
            continue
        ci = grid.continuous_index(at)
        base, frac = [], []
        for a in range(3):
            top = max(grid.dims[a] - 2, 0)
            b = min(max(int(math.floor(ci[a])), 0), top)
            base.append(b)
            frac.append(min(max(ci[a] - b, 0.0), 1.0) if grid.dims[a] > 1 else 0.0)
        corners = []
        for dk in (0, 1):
            for dj in (0, 1):
                for di in (0, 1):
                    w = ((frac[0] if di else 1 - frac[0]) * (frac[1] if dj else 1 - frac[1])
                         * (frac[2] if dk else 1 - frac[2]))
                    index = [min(base[0] + di, grid.dims[0] - 1),
                             min(base[1] + dj, grid.dims[1] - 1),
                             min(base[2] + dk, grid.dims[2] - 1)]
                    if w > 0:
                        corners.append((grid.point_id(index), w))
        samples.append((at, corners))
    return samples, (t1 - t0) / count


def probe_at_pixel(view, x, y, display=None, **probe_args):
    """probe() of the voxel seen at display pixel (x, y) of `view` through `display` (a
    "Gaussian TF Volume" display; default the first visible one in the view). None when
    the ray misses the volume or sees nothing (no opacity along it). The result also
    has `ray` (origin, direction) and `depth` (distance from the ray origin).

    Only the voxels around the ray are read back from the server, in one ExtractVoxels
    round trip that also brings the picked voxel's values (a few thousand voxels, not
    the volume): the ray is sampled every half voxel, the coordinates (float16 ones
    decoded first) and the mask interpolated trilinearly from the 8 voxels around each
    sample, as the ray caster interpolates them."""
    display = display or _gaussian_tf_in(view)
    if display is None:
        raise ValueError("no \"Gaussian TF Volume\" display visible in this view")
    source = display.Input
    grid = _Grid(source)
    origin, direction = pixel_ray(view, x, y)
    hit = _clip_to_box(origin, direction, grid.bounds())
    if hit is None:
        return None
    name = _coordinates_name(display)
    # float16 coordinates too: each voxel's bits are decoded here, and their values
    # interpolated (interpolating the bits themselves, as a server-side probe would, means
    # nothing).
    samples, seg = _ray_samples(grid, origin, direction, hit[0], hit[1], nearest=False)
    voxels = _fetch_voxels(source, sorted(set(i for _, c in samples for i, _ in c)))
    pd = voxels.GetPointData()
    found = pd.GetArray("VoxelId")
    row_of = {int(found.GetValue(r)): r for r in range(found.GetNumberOfTuples())} \
        if found is not None else {}
    coords = pd.GetArray(name)
    if coords is None:
        raise ValueError("the volume has no point array %s (reduced coordinates)" % name)
    mask = pd.GetArray(str(display.MaskArray)) if str(display.MaskArray) else None
    values = {}  # row -> (coordinates, drawn): each voxel decoded once

    def voxel(row):
        if row not in values:
            c = list(_coordinate_tuple(coords, row)) + [0.0]
            drawn = (mask is None or mask.GetTuple1(row) != 0) and \
                all(math.isfinite(v) for v in c)
            values[row] = (c[:3], drawn)
        return values[row]

    widgets = _widget_values(display)
    unit = float(display.ScalarOpacityUnitDistance) or 1.0
    # Composite front to back, as the ray caster does (opacity per unit distance); a
    # sample is drawn where the interpolated mask is at least 1/2.
    keep, opacities = 1.0, []
    for _, corners in samples:
        c, inside, total = [0.0, 0.0, 0.0], 0.0, 0.0
        for pid, w in corners:
            row = row_of.get(pid)
            if row is None:
                continue
            xyz, drawn = voxel(row)
            total += w
            inside += w if drawn else 0.0
            if drawn:
                c = [a + w * b for a, b in zip(c, xyz)]
        alpha = 0.0
        if total > 0 and inside >= 0.5 * total:
            c = [a / inside for a in c]
            alpha = 1.0 - (1.0 - _widget_alpha(widgets, c)) ** (seg / unit)
        keep *= 1.0 - alpha
        opacities.append(1.0 - keep)
    seen = opacities[-1] if opacities else 0.0
    if seen < 1e-3:  # nothing visible along this ray
        return None
    pick = next(p for p, o in enumerate(opacities) if o >= 0.5 * seen)
    point = samples[pick][0]
    probe_args.setdefault("view", view)
    result = probe(display, grid.nearest_index(point), _grid=grid, _fetched=voxels,
                   **probe_args)
    result.ray = (origin, direction)
    result.depth = math.sqrt(sum((a - b) ** 2 for a, b in zip(point, origin)))
    return result


def _domain_in(view):
    """The ReducedDomain whose cloud (port 0) is visible in `view`, or None."""
    from paraview import simple

    for proxy in simple.GetSources().values():
        if proxy.SMProxy.GetXMLName() == "ReducedDomain" and view in _views_showing(proxy, 0):
            return proxy
    return None


def probe_domain_at_pixel(view, x, y, domain=None, tolerance=5, **probe_args):
    """probe() of the voxel whose point of the reduced-domain cloud is seen at display
    pixel (x, y) of the domain view: of the cloud's points within `tolerance` pixels of
    the pixel's ray, the one nearest the camera. `domain`: the ReducedDomain filter
    (default: the one shown in `view`). None when no point is that close."""
    from paraview import servermanager

    domain = domain or _domain_in(view)
    if domain is None:
        raise ValueError("no reduced domain (ReducedDomain) visible in this view")
    origin, direction = pixel_ray(view, x, y)
    height = max(int(view.ViewSize[1]), 1)
    if int(view.CameraParallelProjection):
        per_pixel = lambda t: 2.0 * float(view.CameraParallelScale) / height  # noqa: E731
    else:
        half = math.tan(math.radians(float(view.CameraViewAngle)) / 2.0)
        per_pixel = lambda t: 2.0 * half * t / height  # noqa: E731
    domain.UpdatePipeline(_view_time(view))  # the time step on screen
    cloud = servermanager.Fetch(domain)
    ids = cloud.GetPointData().GetArray("VoxelId")
    best, best_t = None, None
    for p in range(cloud.GetNumberOfPoints()):
        d = [a - b for a, b in zip(cloud.GetPoint(p), origin)]
        t = sum(a * b for a, b in zip(d, direction))
        off2 = sum(a * a for a in d) - t * t
        if t > 0 and off2 <= (tolerance * per_pixel(t)) ** 2 and (best_t is None or t < best_t):
            best, best_t = p, t
    if best is None:
        return None
    probe_args.setdefault("domain_view", view)
    result = probe(domain.Input, int(ids.GetValue(best)), **probe_args)
    result.domain_point = best
    return result
