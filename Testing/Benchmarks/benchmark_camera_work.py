"""What the camera helpers cost a user on the real brain: the Best View button
(apply_best_viewpoint with disambiguate=True, what the GUI's Best View and Explore run) and
one widget edit while the camera follows (follow_best_viewpoint, the GUI's Follow), the
former way against the present one, in one run, beside one plain Render() of the same view
(the floor: a picture has to be drawn once).

    MCV_PLUGIN=build/lib/paraview-5.11/plugins/MultichannelExplorer/MultichannelExplorer.so \
        xvfb-run -a pvbatch Testing/Benchmarks/benchmark_camera_work.py [--rounds 3] [--size 800 600]

Chain (the README's): Colin27 T1 + AAL + Brodmann -> MergeChannels -> reduce_multichannel
(Isomap, 6D) -> "Gaussian TF Volume" with 4 seeded widgets, the camera at the best view.

- Best View, former (main before this change, f95108c, reproduced below): each
  side fitted and rendered, then its screenshot (a second render) for the entropy, then the
  kept side fitted and rendered again: five renders. Present: each side rendered once, by
  its screenshot, "+" last; one render to show the kept side: three.
- Follow, former: every turn at least `frames` (4) rendered steps, however small
  (reproduced by giving the turn's step rule `frames` whatever the move). Present: at most
  90 / frames degrees a step, so a small turn is one render.
Each edit sets the "ch2 mid" widget's opacity (0.20, 0.25, ...): a small turn, as a drag
gives. Lines: median over the rounds, seconds, and the ratio to the plain render.
"""
import argparse
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402


def former_best_view(mce, source, view):
    """apply_best_viewpoint(disambiguate=True) as main ran it before this change."""
    from multichannel_explorer import viewpoint as vp
    from multichannel_explorer.images import _render_entropy

    bvp = vp.best_viewpoint_filter(source, view)
    direction, up = vp._vec(bvp, "BestViewDirection"), vp._vec(bvp, "ViewUp")
    silhouette = vp._visible_points(bvp)
    entropies = {}
    for s, key in ((1, "+"), (-1, "-")):
        vp._fit_camera(view, silhouette, [s * d for d in direction], up)
        entropies[key] = _render_entropy(view)
    sign = 1 if entropies["+"] >= entropies["-"] else -1
    vp._fit_camera(view, silhouette, [sign * d for d in direction], up)
    return sign


def timed(function):
    start = time.perf_counter()
    value = function()
    return time.perf_counter() - start, value


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--size", type=int, nargs=2, default=(800, 600))
    args = p.parse_args()
    mce = T.load_plugin(globals())
    from multichannel_explorer import viewpoint as vp

    channels = [simple.OpenDataFile(T.data_file(n))
                for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
    volume = simple.MergeChannels(Input=channels)
    _, reduced = mce.reduce_multichannel(volume, "Isomap", "6D")
    view = simple.CreateView("RenderView")
    view.ViewSize = list(args.size)
    display = mce.show_gaussian_tf(reduced, view)
    mce.auto_widgets(display, 4)
    mce.apply_best_viewpoint(reduced, view)
    simple.Render(view)

    rows = {"plain render": [], "best view, former": [], "best view, present": [],
            "follow edit, former": [], "follow edit, present": []}
    steps = {"former": [], "present": []}
    original_fractions = vp._animation_fractions
    opacity = 0.2
    for _ in range(args.rounds):
        rows["plain render"].append(timed(lambda: simple.Render(view))[0])
        seconds, sign_former = timed(lambda: former_best_view(mce, reduced, view))
        rows["best view, former"].append(seconds)
        camera_former = [float(x) for x in view.CameraPosition]
        seconds, result = timed(lambda: mce.apply_best_viewpoint(reduced, view,
                                                                  disambiguate=True))
        rows["best view, present"].append(seconds)
        if result.sign != sign_former or max(
                abs(a - b) for a, b in zip(result.camera_position, camera_former)) > 1e-6:
            sys.exit("the former and present Best View keep different sides or cameras")
        follower = mce.follow_best_viewpoint(display, view)
        for way in ("former", "present"):
            if way == "former":  # every turn at least `frames` steps, as before
                vp._animation_fractions = lambda d, least, *a: original_fractions(d, 4, *a)
            opacity += 0.05
            seconds, _ = timed(lambda: mce.edit_widget(display, "ch2 mid", opacity=opacity))
            vp._animation_fractions = original_fractions
            rows["follow edit, " + way].append(seconds)
            steps[way].append(follower.state["result"].steps)
        follower.stop()

    floor = statistics.median(rows["plain render"])
    print("%d x %d view, %d rounds (median seconds; x one plain render)"
          % (args.size[0], args.size[1], args.rounds))
    for name, values in rows.items():
        median = statistics.median(values)
        print("  %-22s %6.2f s  x%.2f" % (name, median, median / floor))
    for kind in ("best view", "follow edit"):
        former = statistics.median(rows[kind + ", former"])
        present = statistics.median(rows[kind + ", present"])
        print("%s: present %.2fx faster than former" % (kind, former / present))
    print("rendered steps per follow edit: former %s, present %s"
          % (steps["former"], steps["present"]))


if __name__ == "__main__":
    main()
