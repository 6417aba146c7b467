#!/bin/sh
# test_gui.sh PARAVIEW: the plugin in the ParaView GUI. Loads it through PV_PLUGIN_PATH,
# opens brainsmall.den as a volume (gui_best_viewpoint_setup.py), clicks the toolbar's
# "Best Viewpoint" button (gui_click_best_viewpoint.xml, QtTesting playback), exits, and
# checks what the button did: apply_best_viewpoint ran with disambiguate=True, gave a
# valid direction, the camera looks along it, the opacity came from the volume display.
# Env: MCV_DATA_DIR, MCV_OUTPUT_DIR, PV_PLUGIN_PATH (set by CTest). Exit 125: no data.
here=$(cd "$(dirname "$0")" && pwd)
paraview="$1"
[ -f "$MCV_DATA_DIR/brainsmall.den" ] || { echo "SKIP: no brainsmall.den"; exit 125; }
mkdir -p "$MCV_OUTPUT_DIR"
state="$MCV_OUTPUT_DIR/gui_state.json"
rm -f "$state" "$MCV_OUTPUT_DIR/gui_after_button.png"
# --dr: default settings (no welcome dialog); a failed playback would wait on a dialog,
# hence the timeout.
sh "$here/run_pvbatch.sh" timeout 150 "$paraview" --dr \
  --script="$here/gui_best_viewpoint_setup.py" \
  --test-script="$here/gui_click_best_viewpoint.xml" --exit
rc=$?
echo "paraview exit status: $rc"
python3 - "$state" "$rc" <<'PY'
import json, math, sys
path, rc = sys.argv[1], int(sys.argv[2])
fails = []
def check(ok, msg):
    print(("ok   " if ok else "FAIL ") + msg)
    if not ok:
        fails.append(msg)
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
print("test_gui: %d failed" % len(fails))
sys.exit(1 if fails else 0)
PY
