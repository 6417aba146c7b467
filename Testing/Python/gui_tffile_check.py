"""GUI test of the Gaussian widget editor's Save... and Load..., part 3 (run by test_gui.sh
with the state file and paraview's exit status): Save... wrote saved.mcvtf with the two
widgets and the fitted model beside it (saved.mcvmodel); Add made three widgets; Load...
set the reduction's ModelFile to that model and the two widgets again; Edit > Undo took
both back in one step (three widgets, no ModelFile). The widgets' names go into the file and
come back with Load...."""
import json
import os

from gui_checks import arguments, check, finish, load_state  # noqa: E402

path, rc = arguments()
check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
state = load_state(path)
initial = state.get("initial", [])
events = state.get("events", [])
folder = state.get("folder", "")
print("recorded: %s" % [(k, v if k == "model" else len(v) // 8) for k, v in events])
saved = os.path.join(folder, "saved.mcvtf")
model = os.path.join(folder, "saved.mcvmodel")
try:
    with open(saved) as f:
        content = json.load(f)
except (OSError, ValueError) as e:
    content = {}
    check(False, "Save... wrote %s (%s)" % (saved, e))
if content:
    values = []
    for w in content["widgets"]:
        values += w["centre"] + [w["sigma"]] + w["colour"] + [w["opacity"]]
    check(values == initial and content["model"]["file"] == "saved.mcvmodel" and
          os.path.exists(model),
          "Save... wrote the two widgets exactly, and the model saved.mcvmodel beside them")
    check([w.get("name") for w in content["widgets"]] == state.get("initial_names"),
          "Save... wrote the widgets' names %s" % [w.get("name") for w in content["widgets"]])
widgets = [v for k, v in events if k == "widgets"]
models = [v for k, v in events if k == "model"]
check(len(widgets) >= 1 and len(widgets[0]) == 24 and widgets[0][:16] == initial,
      "Add made a third widget after the two")
check(len(models) >= 1 and os.path.normpath(models[0]) == os.path.normpath(model),
      "Load... set the reduction's ModelFile to the saved model (%s)" % models[:1])
after_load = [i for i, (k, v) in enumerate(events) if k == "widgets" and v == initial]
check(len(after_load) >= 1 and len(widgets) >= 2 and widgets[1] == initial,
      "Load... set the two saved widgets again")
names = state.get("names_at_widgets", [])
check(len(names) >= 2 and names[1] == state.get("initial_names"),
      "Load... set their names again, with the widgets: %s" % names[1:2])
check(len(events) >= 2 and events[-1][0] in ("widgets", "model") and
      widgets[-1] == widgets[0] and models[-1] == "",
      "Edit > Undo: the three widgets and no ModelFile again (one undo step)")
finish("gui_tffile")
