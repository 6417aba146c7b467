"""GUI test, part 3 (run by test_gui.sh with the state file and paraview's exit status):
what the "Best Viewpoint" button did."""
import json
import math

from gui_checks import arguments, check, fails, finish  # noqa: F401

path, rc = arguments()
check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
try:
    s = json.load(open(path))
except Exception as e:
    s = {}
    check(False, "state file %s readable (%s)" % (path, e))
check(s.get("loaded") == "VolPackDenReader", "brainsmall.den opened by the plugin's reader")
check(s.get("called") is True, "the toolbar button called apply_best_viewpoint")
check("disambiguate" in s.get("kwargs", []), "... with disambiguate")
check(s.get("valid") is True, "... and got a valid direction")
check(s.get("opacity_from_display") is True, "... from the volume display's opacity")
if s.get("called"):
    d = [f - p for f, p in zip(s["camera_focal_point"], s["camera_position"])]
    n = math.sqrt(sum(x * x for x in d))
    c = sum(x * y for x, y in zip(d, s["direction"])) / n
    check(c > 0.99999, "camera looks along the chosen direction (cos %.6f)" % c)
    check(abs(abs(sum(x * y for x, y in zip(s["direction"], s["best"]))) - 1) < 1e-9,
          "the chosen direction is +-BestViewDirection")
    check(s["camera_position"] != s["before"], "the camera moved")
finish("test_gui")
