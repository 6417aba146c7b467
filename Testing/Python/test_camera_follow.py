"""(k) The camera follows smoothly.

* Known answers of the pure math in multichannel_explorer.viewpoint: slerp endpoints and
  midpoint, the swing about the view-up for opposite directions, the sign choice of v / -v,
  the time-based step fractions (with a fake clock: fast and slow renders).
* follow_best_viewpoint on a synthetic volume whose coordinates are the voxel positions,
  Gaussian widgets on a plane (best view = its normal): every rendered camera of an update
  is recorded (an EndEvent observer on the render window) and the path must be on the great
  circle, in small steps, at a constant distance, with the view-up carried along (no roll,
  no flip), over about 0.5 s, ending exactly (1e-6) on the filter's direction up to sign.
* A new best direction within 90 degrees of the negated camera direction: the camera takes
  -v (the nearer sign) and turns by less than 90 degrees.
* Widgets off the grid's middle: the turn ends on the middle of the voxels they show
  (VisibleBounds), not on the grid's centre.
* turn_camera with an explicit view-up ends on it; opposite directions swing about the up.
"""
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_camera_follow")
out = T.output_dir()
vp = mce.viewpoint
FRAMES = 6  # at least this many rendered steps per turn


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def close(a, b, tol=1e-12):
    return max(abs(x - y) for x, y in zip(a, b)) <= tol


# ---- pure math: known answers -------------------------------------------------------------
a, b = [1.0, 0.0, 0.0], T.unit([0.3, 0.9, 0.1])
C.check(vp._slerp(a, b, 0.0) == a and vp._slerp(a, b, 1.0) == b,
        "slerp: t = 0 gives a, t = 1 gives b exactly")
mid = vp._slerp([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 0.5)
C.check(close(mid, [math.sqrt(0.5), math.sqrt(0.5), 0.0]),
        "slerp: half way from x to y is (x + y)/sqrt(2) %s" % mid)
quarter = vp._slerp(a, b, 0.25)
C.check(abs(T.angle_deg(a, quarter) - 0.25 * T.angle_deg(a, b)) < 1e-9
        and abs(T.norm(quarter) - 1) < 1e-12 and abs(T.dot(quarter, cross(a, b))) < 1e-12,
        "slerp: a quarter of the angle, unit length, on the great circle")
swing = vp._slerp([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 0.5, [0.0, 0.0, 1.0])
C.check(close(swing, [0.0, 1.0, 0.0]),
        "slerp to the opposite direction turns about the hint (view-up): %s" % swing)

C.check(vp._continuous_sign([0, 0, 1], [0.1, 0.0, 1.0]) == 1,
        "sign: v within 90 deg of the camera direction is kept")
C.check(vp._continuous_sign([0, 0, 1], [1.0, 0.0, -0.02]) == -1
        and vp._continuous_sign([0, 0, 1], [0.1, 0.0, -1.0]) == -1,
        "sign: v within 90 deg of -camera direction (91 and 174 deg away) gives -v")


def fractions(render_seconds, duration=0.5, min_steps=4):
    """Step fractions and the time they took, each render taking render_seconds."""
    now = [0.0]

    def clock():
        return now[0]

    def sleep(seconds):
        now[0] += seconds

    ts = []
    for t in vp._animation_fractions(duration, min_steps, clock, sleep):
        ts.append(t)
        now[0] += render_seconds
    return ts, now[0]


for render_seconds in (0.001, 0.05, 0.3):
    ts, spent = fractions(render_seconds)
    steps = [y - x for x, y in zip([0.0] + ts, ts)]
    C.check(ts[-1] == 1.0 and all(s > 0 for s in steps) and max(steps) <= 0.25 + 1e-12
            and len(ts) >= 4,
            "fractions (%.3f s renders): %d steps, increasing, none over 1/4, last 1"
            % (render_seconds, len(ts)))
    # Time-based: fast renders fill about 0.5 s (60 steps a second at most); slow ones
    # take as long as their at least 4 steps need.
    expected = max(0.5, 4 * render_seconds)
    C.check(abs(spent - expected) <= 0.5 / 30 + 2 * render_seconds + 1e-9,
            "fractions (%.3f s renders): %.3f s spent, about %.3f" % (render_seconds, spent,
                                                                      expected))
C.check(len(fractions(0.001)[0]) <= 31, "fractions: fast renders give at most 60 steps/s")
C.check(list(vp._animation_fractions(0.5, 1)) == [1.0]
        and list(vp._animation_fractions(0, 4)) == [0.25, 0.5, 0.75, 1.0],
        "fractions: frames=1 at once; duration 0: equal steps")

# ---- the camera path of follow_best_viewpoint ---------------------------------------------


def plane_widgets(normal, spread=9.0, sigma=2.5, color=(1.0, 0.3, 0.1)):
    """5 widgets on the plane through the origin with this normal (a cross)."""
    n = T.unit(normal)
    u = T.unit(cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]))
    w = cross(n, u)
    flat = list([0.0, 0.0, 0.0, sigma] + list(color) + [1.0])
    for axis in (u, w):
        for s in (-1.0, 1.0):
            flat += [s * spread * x for x in axis] + [sigma] + list(color) + [1.0]
    return flat


wavelet = Wavelet(WholeExtent=[-20, 20, -20, 20, -20, 20])
coords = Calculator(Input=wavelet, Function="coords", ResultArrayName="ReducedCoordinates",
                    ResultArrayType="Float")
view = CreateView("RenderView")
view.ViewSize = [300, 300]
display = mce.show_gaussian_tf(coords, view, widgets=plane_widgets([1.0, 2.0, 2.0]))
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraPosition = [60.0, 20.0, 10.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
Render(view)

camera = view.GetActiveCamera()
path = []  # (seconds, direction, view-up, distance, focal point) of every render


def on_render(*unused):
    path.append((time.monotonic(), list(camera.GetDirectionOfProjection()),
                 list(camera.GetViewUp()), camera.GetDistance(), list(camera.GetFocalPoint())))


view.GetRenderWindow().AddObserver("EndEvent", on_render)
follower = mce.follow_best_viewpoint(display, view, frames=FRAMES)


def check_path(label, result):
    """The recorded path of one turn: continuous, on the great circle, no roll, distance
    kept, about 0.5 s, ending exactly on sign * the filter's direction."""
    end_time, goal, goal_up, _, _ = path[-1]
    total = T.angle_deg(start_direction, goal)
    # at least FRAMES steps for a 90 degree turn, proportionally fewer for a smaller one
    least = max(1, int(math.ceil(total / 90.0 * FRAMES - 1e-9)))
    C.check(result is not None and len(path) == result.steps >= least,
            "%s: %d rendered steps (at least %d for %.1f deg), all recorded"
            % (label, len(path), least, total))
    if len(path) < 2:
        return
    t0, d0, up0, dist0, _ = path[0]
    best = result.best
    C.check(close(goal, [result.sign * x for x in best], 1e-6),
            "%s: ends along %+d * the filter's direction (1e-6; off by %.2g)"
            % (label, result.sign, max(abs(g - result.sign * x) for g, x in zip(goal, best))))
    C.check(result.sign == vp._continuous_sign(start_direction, best),
            "%s: of v and -v the one nearer the camera before the turn" % label)
    axis = T.unit(cross(start_direction, goal))
    angles = [T.angle_deg(start_direction, p[1]) for p in path]
    steps = [T.angle_deg(p[1], q[1]) for p, q in zip(path, path[1:])]
    C.check(max(steps) <= 90.0 / FRAMES + 1e-4 and total < 90.0,
            "%s: a %.1f deg turn in steps of at most %.2f deg (largest %.2f)"
            % (label, total, 90.0 / FRAMES, max(steps)))
    C.check(all(abs(T.dot(p[1], axis)) < 1e-6 for p in path)
            and all(y > x for x, y in zip(angles, angles[1:])),
            "%s: every direction on the great circle, turning one way" % label)
    carried = [vp._rotate(start_up, axis, math.radians(x)) for x in angles]
    roll = max(T.angle_deg(p[2], c) for p, c in zip(path, carried))
    C.check(roll < 1e-4 and all(abs(T.dot(p[1], p[2])) < 1e-6 for p in path),
            "%s: view-up carried along the turn, perpendicular (largest roll %.2g deg)"
            % (label, roll))
    ups = [T.angle_deg(p[2], q[2]) for p, q in zip(path, path[1:])]
    C.check(max(ups) <= max(steps) + 1e-4, "%s: view-up continuous (largest step %.2f deg)"
            % (label, max(ups)))
    C.check(max(abs(p[3] - start_distance) for p in path) < 1e-6 * start_distance,
            "%s: distance kept (%.3f)" % (label, start_distance))
    # Time-based: about 0.5 s from the first step to the last (the first comes after
    # 1/30 of it, and a slow render may stretch it to FRAMES steps).
    spent = end_time - t0
    longest = max(q[0] - p[0] for p, q in zip(path, path[1:]))
    C.check(0.4 <= spent <= max(0.5, FRAMES * longest) + 0.1,
            "%s: %.2f s from the first step to the last (about 0.5 s; longest step %.3f s)"
            % (label, spent, longest))


def start_turn():
    """Camera before the next turn; starts a new path."""
    global start_direction, start_up, start_distance
    del path[:]
    start_direction = list(camera.GetDirectionOfProjection())
    start_up = T.unit(list(camera.GetViewUp()))
    start_up = T.unit([u - T.dot(start_up, start_direction) * d
                       for u, d in zip(start_up, start_direction)])
    start_distance = camera.GetDistance()
    

# Widgets on a new plane: the observer recomputes the best view and turns the camera.
start_turn()
bvp = follower.state["result"].filter
display.GaussianWidgets = plane_widgets([2.0, -1.0, 0.5], color=(0.1, 0.4, 1.0))
result_b = follower.state["result"]
check_path("widget change", result_b)
C.check(T.angle_deg(result_b.best, [2.0, -1.0, 0.5], unsigned=True) < 2.0,
        "widget change: the filter's direction is the new plane's normal")
SaveScreenshot(os.path.join(out, "camera_follow_b.png"), view)

# A best direction v within 90 degrees of -camera: the camera must take -v, not flip.
widgets_c = plane_widgets([0.2, 1.0, -0.6], color=(0.2, 0.9, 0.3))
bvp.GaussianWidgets = widgets_c
bvp.UpdatePipeline()
bvp.UpdatePropertyInformation()
v = [float(x) for x in bvp.GetPropertyValue("BestViewDirection")]
side = T.unit(cross(v, [0.0, 0.0, 1.0]))
towards = T.unit([-x + 0.9 * s for x, s in zip(v, side)])  # 42 deg from -v, 138 from v
view.CameraPosition = [-40.0 * x for x in towards]
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraViewUp = cross(side, towards)
Render(view)
start_turn()
display.GaussianWidgets = widgets_c
result_c = follower.state["result"]
C.check(result_c.sign == -1 and close(result_c.best, v, 1e-12),
        "new direction within 90 deg of -camera (%.0f deg from -v): the camera takes -v"
        % T.angle_deg(towards, [-x for x in v]))
check_path("no flip", result_c)

# Widgets off the volume's middle: the turn ends with the focal point in the middle of the
# voxels they show (the filter's VisibleBounds), not at the grid's centre.
display.GaussianWidgets = [x + 9.0 if i % 8 < 3 else x
                           for i, x in enumerate(plane_widgets([1.0, 0.0, 0.0], spread=4.0))]
result_d = follower.state["result"]
visible = [float(v) for v in result_d.filter.GetProperty("VisibleBounds")]
middle = [(visible[2 * a] + visible[2 * a + 1]) / 2.0 for a in range(3)]
focal = list(camera.GetFocalPoint())
C.check(close(focal, middle, 1e-6) and min(middle) > 5.0,
        "off-centre widgets: the camera turns about the middle of what they show %s "
        "(VisibleBounds %s), not the grid's centre (0, 0, 0)"
        % (["%.2f" % f for f in focal], ["%.1f" % b for b in visible]))
follower.stop()

# ---- turn_camera with an explicit view-up; opposite directions -------------------------------
start_turn()
goal = T.unit([0.3, -0.5, 0.8])
want_up = T.unit(cross(goal, [1.0, 0.0, 0.0]))
steps = mce.turn_camera(view, [0.0, 0.0, 0.0], goal, want_up, frames=FRAMES)
C.check(steps == len(path) >= FRAMES and close(path[-1][1], goal, 1e-6)
        and close(T.unit(path[-1][2]), want_up, 1e-6),
        "turn_camera(view_up=...): ends on the direction and on the view-up (%d steps)" % steps)
C.check(max(T.angle_deg(p[2], q[2]) for p, q in zip(path, path[1:]))
        <= max(T.angle_deg(p[1], q[1]) for p, q in zip(path, path[1:])) + 180.0 / FRAMES + 1e-3
        and all(abs(T.dot(p[1], p[2])) < 1e-6 for p in path),
        "turn_camera(view_up=...): the roll spread over the steps, up perpendicular")
start_turn()
mce.turn_camera(view, [0.0, 0.0, 0.0], [-x for x in goal], frames=FRAMES)
C.check(close(path[-1][1], [-x for x in goal], 1e-6)
        and max(T.angle_deg(p[2], want_up) for p in path) < 1e-4
        and max(T.angle_deg(p[1], q[1]) for p, q in zip(path, path[1:])) <= 180.0 / FRAMES + 1e-4,
        "turn_camera to the opposite direction: swings about the view-up (no roll)")

# ---- turn_camera(fit=...): the turn ends framed as apply_best_viewpoint frames ---------------
display.GaussianWidgets = plane_widgets([1.0, 2.0, 2.0])
framed = mce.apply_best_viewpoint(coords, view)
want = (list(camera.GetPosition()), list(camera.GetFocalPoint()), list(camera.GetViewUp()))
camera.Azimuth(40.0)
camera.Dolly(0.5)  # twice as far
camera.OrthogonalizeViewUp()
Render(view)
start_turn()
steps = mce.turn_camera(view, None, framed.direction, framed.view_up, frames=FRAMES, fit=framed.filter)
got = (list(camera.GetPosition()), list(camera.GetFocalPoint()), list(camera.GetViewUp()))
scale = camera.GetDistance()
C.check(close(got[0], want[0], 1e-6 * scale) and close(got[1], want[1], 1e-6 * scale)
        and close(got[2], want[2], 1e-6),
        "turn_camera(fit=...): ends on apply_best_viewpoint's camera (position off by %.2g)"
        % max(abs(a - b) for a, b in zip(got[0], want[0])))
distances = [p[3] for p in path]
C.check(len(path) == steps and all(y < x for x, y in zip(distances, distances[1:])),
        "turn_camera(fit=...): the distance shrinks at every step (%s)"
        % ["%.1f" % d for d in distances])

# ---- a slow renderer: as many steps as the move needs; duration 0: exactly `frames` ------------
def turned_by(degrees, slide=0.0, duration=1e-6):
    """Steps of a turn by `degrees` about the view-up, the focal point slid by `slide`;
    every render outlasts a duration of 1e-6 s: the slowest renderer."""
    focal, direction = list(camera.GetFocalPoint()), list(camera.GetDirectionOfProjection())
    up = T.unit(list(camera.GetViewUp()))
    goal = vp._rotate(direction, up, math.radians(degrees))
    start_turn()
    steps = mce.turn_camera(view, [f + slide * u for f, u in zip(focal, up)], goal,
                            frames=FRAMES, duration=duration)
    return steps, len(path)


for degrees, slide, want in ((5.0, 0.0, 1), (14.0, 0.0, 1), (16.0, 0.0, 2), (50.0, 0.0, 4),
                             (120.0, 0.0, FRAMES), (0.0, 0.5 * camera.GetDistance(), 2)):
    got = turned_by(degrees, slide)
    C.check(got == (want, want),
            "turn_camera, slow renderer: a %.0f deg turn%s in %d rendered steps (%s)"
            % (degrees, " and a slide of half the distance" if slide else "", want, got))
got = turned_by(5.0, duration=0)
C.check(got == (FRAMES, FRAMES),
        "turn_camera, duration 0 (a batch script's movie frames): a 5 deg turn in exactly "
        "frames = %d steps (%s)" % (FRAMES, got))
C.finish()
