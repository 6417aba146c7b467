"""GUI test of Follow Best Viewpoint + Seed Gaussian Widgets, part 3 (run by test_gui.sh
with the state file and paraview's exit status): the toggle started following (camera
along the widgets' plane normal, z), the seed button set 4 widgets on the display, and
the follower turned the camera to the new widgets' best view, computed from their
opacity, in several small rendered steps (the helper's animation)."""
import math

from gui_checks import arguments, check, fails, finish, recorded_events  # noqa: E402,F401

path, rc = arguments()


def cosine(a, b):
    return abs(sum(x * y for x, y in zip(a, b))) / math.sqrt(
        sum(x * x for x in a) * sum(y * y for y in b))


def angle(a, b):
    c = sum(x * y for x, y in zip(a, b)) / math.sqrt(sum(x * x for x in a) * sum(y * y for y in b))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def check_animation(before, path):
    """The toggle's turn is the helper's animation: at least 4 rendered steps (its default
    `frames`), none more than a quarter of the turn, the view-up never flipping."""
    directions = [before] + [p[0] for p in path]
    steps = [angle(a, b) for a, b in zip(directions, directions[1:])]
    moving = [x for x in steps if x > 1e-6]
    total = angle(before, directions[-1])
    ups = [angle(p[1], q[1]) for p, q in zip(path, path[1:])]
    if check(len(moving) >= 4, "... in %d rendered steps (at least 4)" % len(moving)):
        check(max(moving) <= total / 4.0 + 1e-3 and max(ups) < 45.0,
              "... each at most a quarter of the %.1f deg turn (largest %.2f deg; view-up "
              "%.2f deg)" % (total, max(moving), max(ups)))


events = recorded_events(path, rc)
follow = [e for e in events if e["event"] == "follow"]
seed = [e for e in events if e["event"] == "seed"]
if check(len(follow) == 1 and follow[0]["best"], "the toggle called follow_best_viewpoint"):
    check(cosine(follow[0]["camera"], [0, 0, 1]) > 0.999,
          "... the camera looks along the plane normal (cos %.5f)"
          % cosine(follow[0]["camera"], [0, 0, 1]))
if check(len(seed) == 1, "the seed button called auto_widgets"):
    s = seed[0]
    check(s["widgets"] == 32 and s["display_widgets"] == 32,
          "... 4 widgets set on the display (%d values)" % s["display_widgets"])
    source = s["opacity_source"].strip("'\"")  # str() of the property keeps its quotes
    check(source in ("1", "Representation") and s["filter_widgets"] == s["display_values"],
          "... the best viewpoint was recomputed from the new widgets' opacity")
    check(cosine(s["camera"], s["best"]) > 0.99999,
          "... and the camera turned to it (cos %.6f)" % cosine(s["camera"], s["best"]))
    check_animation(s["before"], s.get("path", []))
finish("gui_follow")
