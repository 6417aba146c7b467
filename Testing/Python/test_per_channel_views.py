"""Examples/per_channel_views.py on the real 3-channel brain (Colin27 T1, AAL, Brodmann):
each picture shows the channel it is named after, at that channel's best view.

Known answers:
- MergeChannels names the channels after the files but does not keep the files' order:
  every channel array has its picture, named after it, coloured by it (report.json's
  coloured_by), and all.png shows them together (the array all_channels);
- each picture's direction is the best view of its channel alone, computed here by a
  BestViewpoint filter of its own (Channels = that channel, the default opacity: the
  channel's range linearly, as the example asks with OpacityFunction=None), up to the sign;
- the T1's best view differs from the atlases' (they show different structures).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_per_channel_views")
files = [T.data_file(n + ".nii.gz") for n in T.BRAIN]
out = os.path.join(T.output_dir(), "per_channel_views_check")
report = T.run_example(C, "per_channel_views.py", ["--output", out, "--channels"] + files, out)

volume = simple.MergeChannels(Input=[simple.OpenDataFile(f) for f in files])
volume.UpdatePipeline()
names = list(volume.PointData.keys())
by_image = {v["image"]: v for v in report}
C.check(sorted(by_image) == sorted(["all.png"] + [n + ".png" for n in names]),
        "one picture per channel array, named after it, and all.png: %s" % sorted(by_image))
C.check(by_image.get("all.png", {}).get("channels") == names and
        by_image["all.png"].get("coloured_by") == "all_channels",
        "all.png: the view of every channel, drawn by all_channels (%s)"
        % by_image.get("all.png", {}).get("coloured_by"))
directions = {}
for name in names:
    view = by_image.get(name + ".png")
    if not C.check(view is not None, "%s.png listed" % name):
        continue
    picture = os.path.join(out, view["image"])
    C.check(view["channels"] == [name] and view["coloured_by"] == name,
            "%s: shows its own channel (channels %s, coloured by %s)"
            % (view["image"], view["channels"], view["coloured_by"]))
    C.check(os.path.exists(picture) and not T.blank_picture(picture),
            "%s: written, not blank" % view["image"])
    own = mce.best_viewpoint_filter(volume, None, Channels=[name], OpacityFunction=None)
    expected = [float(v) for v in own.GetPropertyValue("BestViewDirection")]
    cosine = abs(sum(a * b for a, b in zip(expected, view["direction"])))
    C.check(cosine > 0.9999, "%s: the best view of %s alone (%.2f deg from this test's "
            "filter)" % (view["image"], name, math.degrees(math.acos(min(1.0, cosine)))))
    directions[name] = view["direction"]
if len(directions) == 3:
    cosines = [abs(sum(a * b for a, b in zip(directions["ch2"], directions[atlas])))
               for atlas in ("aal", "brodmann")]
    C.check(max(cosines) < math.cos(math.radians(5)),
            "the T1's best view is more than 5 deg from each atlas' (%s deg)"
            % ["%.1f" % math.degrees(math.acos(min(1.0, c))) for c in cosines])
C.finish()
