"""(h) The main job (Examples/transfer_function.py) on the real 3-channel brain, small
settings (6D features, a 2000-voxel reference sample): features -> Isomap -> seeded
widgets -> Gaussian TF Volume -> best viewpoint of the widgets' opacity.

Checks the report (every stage timed, finite trustworthiness and variance retained, a
valid best direction perpendicular to the worst one), that every image is written and
not blank, and that the best-view image shows the seeded widgets' colours: pixels whose
colour is near a widget's hue, for at least two widgets.
"""
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_main_job")
out = os.path.join(T.output_dir(), "main_job")
for name in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"):
    T.data_file(name)

command = [sys.executable if os.path.basename(sys.executable).startswith("pv") else "pvbatch",
           os.path.join(T.REPO, "Examples", "transfer_function.py"),
           "--features", "6D", "--reference-size", "2000", "--landmarks", "200",
           "--widgets", "3", "--size", "480", "360", "--output", out]
if os.environ.get("MCV_PLUGIN"):
    command += ["--plugin", os.environ["MCV_PLUGIN"]]
# Under its own X server through run_pvbatch.sh, which retries a lost X server as it does
# for every test (a nested pvbatch on this test's display had no such retry).
run = subprocess.run(["sh", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                         "run_pvbatch.sh"), "pvbatch"] + command[1:],
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
print(run.stdout[-3000:])
C.check(run.returncode == 0, "Examples/transfer_function.py ran (exit %d)" % run.returncode)
C.check("output: " in run.stdout, "it printed the output folder")

report_path = os.path.join(out, "report.json")
if not C.check(os.path.exists(report_path), "report.json written"):
    C.finish()
with open(report_path) as f:
    report = json.load(f)
C.check(set(report["stage_seconds"]) >= {"read", "features", "reduction", "seed widgets",
                                         "best viewpoint", "dual domain"},
        "report: every stage timed %s" % sorted(report["stage_seconds"]))
C.check(0.0 < report["variance_retained"] <= 1.0 and 0.5 < report["trustworthiness"] <= 1.0,
        "report: variance retained %.3f, trustworthiness %.3f"
        % (report["variance_retained"], report["trustworthiness"]))
best, worst = report["best_direction"], report["worst_direction"]
C.check(abs(T.norm(best) - 1) < 1e-6 and abs(T.dot(best, worst)) < 1e-6,
        "report: unit best direction perpendicular to the worst")
C.check(len(report["widgets"]) == 3, "report: 3 widgets seeded")

for name in ("best", "worst", "dual_domain", "domain", "spectrum"):
    T.image_ok(mce, os.path.join(out, name + ".png"), C, name, min_stddev=4.0,
               min_fraction=0.02)


def hue(rgb):
    r, g, b = rgb
    mx, mn = max(rgb), min(rgb)
    if mx - mn < 1e-9:
        return None
    if mx == r:
        h = ((g - b) / (mx - mn)) % 6
    elif mx == g:
        h = (b - r) / (mx - mn) + 2
    else:
        h = (r - g) / (mx - mn) + 4
    return h / 6.0


image = mce._read_png(os.path.join(out, "best.png"))
pixels = image.GetPointData().GetScalars()
counts = [0] * len(report["widgets"])
for i in range(pixels.GetNumberOfTuples()):
    p = pixels.GetTuple(i)[:3]
    if max(p) - min(p) < 40:  # grey: background or faint
        continue
    h = hue([c / 255.0 for c in p])
    for w, widget in enumerate(report["widgets"]):
        wh = hue(widget[4:7])
        if wh is not None and min(abs(h - wh), 1 - abs(h - wh)) < 0.04:
            counts[w] += 1
C.check(sum(1 for c in counts if c > 50) >= 2,
        "best view shows the widgets' colours (pixels per widget hue: %s)" % counts)
C.finish()
