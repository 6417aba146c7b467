"""GUI test "ParaView's own Save State (.py) loads the plugin", part 3 (run by test_gui.sh
with the state file and paraview's exit status; plain python3). The Python state that
File > Save State wrote, with the plugin only loaded (no button of it pressed, nothing
imported by the test), has the plugin's LoadPlugin line after `from paraview.simple import
*` and before the first proxy it creates; run in a fresh pvbatch without the plugin
preloaded ($MCV_PVBATCH, no PV_PLUGIN_PATH) it loads the plugin and builds the GUI's
pipeline (the reader, DimensionReduction1 on it), whose reduction updates over every voxel.
The same file without its LoadPlugin lines fails there on the plugin's first proxy: the
lines are what loads it."""
import json
import os

from gui_checks import arguments, check, finish, state_with_data
import mcv_testing as T

here = os.path.dirname(os.path.abspath(__file__))
path, rc = arguments()
s = state_with_data(path, rc, "small_64D.nii")
saved = s.get("saved", "")
text = open(saved).read() if os.path.isfile(saved) else ""
check(bool(text), "File > Save State wrote the Python state %s" % saved)
lines = text.split("\n")


def first(predicate):
    return next((i for i, line in enumerate(lines) if predicate(line.strip())), None)


imports = first(lambda l: l == "from paraview.simple import *")
load = first(lambda l: l.startswith("LoadPlugin(") and "MultichannelExplorer" in l)
creates = first(lambda l: "DimensionReduction(" in l or "OpenDataFile(" in l or
                ("(registrationName=" in l and not l.startswith("#")))
check(imports is not None and load is not None and creates is not None and
      imports < load < creates,
      "the state loads the plugin after `from paraview.simple import *` (line %s) and before "
      "it creates the first proxy (line %s): line %s: %s"
      % (imports, creates, load, lines[load] if load is not None else None))


def run_state(state_path, name):
    """Runs state_path in a fresh pvbatch without the plugin preloaded; its JSON report."""
    report = os.path.join(os.path.dirname(saved), name)
    if os.path.exists(report):
        os.remove(report)
    env = dict(os.environ)
    env.pop("PV_PLUGIN_PATH", None)
    proc = T.run_pvbatch(os.environ["MCV_PVBATCH"], [
        os.path.join(here, "gui_save_state_load.py"), state_path, report], env=env, timeout=300)
    try:
        with open(report) as f:
            return json.load(f)
    except (OSError, ValueError):
        print(proc.stdout[-3000:])
        return {}


reader_name, reader_type = s.get("reader", [None, None])
expected = {reader_name: [reader_type, []], "DimensionReduction1": ["DimensionReduction",
                                                                   [reader_name]]}
if text:
    got = run_state(saved, "gui_save_state_load.json")
    check(got.get("preloaded") is False and got.get("error") is None and
          got.get("plugin_loaded") is True,
          "a fresh pvbatch without the plugin ran the state, which loaded the plugin "
          "(error: %s)" % got.get("error"))
    check(got.get("sources") == expected,
          "the state built the GUI's pipeline %s (got %s)" % (expected, got.get("sources")))
    reduction = got.get("reduction") or {}
    check(reduction.get("points") == s.get("points") and reduction.get("components", 0) >= 1,
          "its DimensionReduction1 updates: ReducedCoordinates on all %s voxels (%s)"
          % (s.get("points"), reduction))

    stripped = os.path.join(os.path.dirname(saved), "gui_save_state_without_plugin.py")
    with open(stripped, "w") as f:
        f.write("\n".join(l for l in lines if not l.strip().startswith("LoadPlugin(")))
    bare = run_state(stripped, "gui_save_state_without_plugin.json")
    check(bare.get("plugin_loaded") is False and bool(bare.get("error")) and
          "DimensionReduction1" not in (bare.get("sources") or {}),
          "without its LoadPlugin lines the same state fails in a fresh pvbatch (%s)"
          % (bare.get("error") or "").strip().split("\n")[-1:])
finish("gui_save_state")
