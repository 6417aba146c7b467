"""The ray samples of a frame through a volume's box, as VTK's ray caster takes them without
early termination: used by the frame-time benchmarks to turn a frame time into a time per
sample (benchmark_handle_move.py --turn, benchmark_sample_fetch.py)."""
import math

import numpy as np


def box_samples(camera, size, bounds, distance):
    """Ray samples of a frame through the box `bounds` at the sample distance `distance`,
    without early termination: the sum over the `size` = (width, height) pixels of each
    ray's chord in the box over that distance. `camera`: a vtkCamera (perspective)."""
    width, height = [int(v) for v in size]
    eye = np.array(camera.GetPosition())
    forward = np.array(camera.GetFocalPoint()) - eye
    forward /= np.linalg.norm(forward)
    up = np.array(camera.GetViewUp())
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = math.tan(math.radians(camera.GetViewAngle()) / 2.0)  # vertical half-angle
    ys, xs = np.mgrid[0:height, 0:width]
    u = ((xs + 0.5) / width * 2 - 1) * half * width / height
    v = ((ys + 0.5) / height * 2 - 1) * half
    dirs = forward[None, None, :] + u[..., None] * right + v[..., None] * up
    dirs /= np.linalg.norm(dirs, axis=2)[..., None]
    lo = np.array(bounds[0::2]) - eye
    hi = np.array(bounds[1::2]) - eye
    with np.errstate(divide="ignore", invalid="ignore"):
        t0 = np.where(dirs != 0, lo / dirs, -np.inf)
        t1 = np.where(dirs != 0, hi / dirs, np.inf)
    near = np.maximum(np.minimum(t0, t1).max(axis=2), 0)
    far = np.maximum(t0, t1).min(axis=2)
    chord = np.clip(far - near, 0, None)
    return float(chord.sum() / distance)
