"""GUI test of the Gaussian widget editor, part 3 (run by test_gui.sh with the state file
and paraview's exit status): each edit of gui_editor_click.xml reached GaussianWidgets at
once, as one change, with the expected values (duplicate appends a copy of the selected
widget and selects it, remove takes the selected one away); hiding wrote opacity 0 and
remembered the opacity in GaussianWidgetsHidden; Edit > Undo restored the widgets before
the hide; Seed from clusters set the 3 widgets auto_widgets returned."""
import json

from gui_checks import arguments, check, fails, finish  # noqa: E402,F401

path, rc = arguments()


def close(a, b, tol=1e-9):
    return len(a) == len(b) and all(abs(x - y) <= tol for x, y in zip(a, b))


FIRST = [0, 0, 0, 4, 1, 0.4, 0.1, 0.8]
# Add: at the domain centre (0, 0, 0), sigma a tenth of the 40-wide domain, opacity 0.5,
# the editor's second palette colour (ColorBrewer Set1 blue, #377EB8).
added = [0, 0, 0, 4, 0x37 / 255, 0x7E / 255, 0xB8 / 255, 0.5]
red = added[:4] + [1, 0, 0] + added[7:]
sigma = red[:3] + [2.5] + red[4:]
opacity = sigma[:7] + [0.7]
moved = [5] + opacity[1:]
hidden = moved[:7] + [0]
steps = [("add", FIRST + added), ("colour", FIRST + red), ("sigma", FIRST + sigma),
         ("opacity", FIRST + opacity), ("centre x", FIRST + moved),
         ("duplicate", FIRST + moved + moved), ("remove the copy", FIRST + moved),
         ("hide", FIRST + hidden),
         ("undo", FIRST + moved)]

check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
try:
    recorded = json.load(open(path))
except Exception as e:  # noqa: BLE001
    recorded = {"states": [], "hidden": []}
    check(False, "state file %s readable (%s)" % (path, e))
states, hidden_states = recorded["states"], recorded["hidden"]
print("recorded %d changes of GaussianWidgets, %d of GaussianWidgetsHidden"
      % (len(states), len(hidden_states)))
for i, s in enumerate(states):
    print("  %d: %s" % (i, s))
check(len(states) >= len(steps) + 1,
      "%d editor edits, each one change of GaussianWidgets, then the seed (%d changes)"
      % (len(steps), len(states)))
for (name, expected), s in zip(steps, states):
    check(close(s, expected), "%s: GaussianWidgets = %s" % (name, expected))
# Seed from clusters: the widgets auto_widgets returned replace all the others (Python
# sets the property in two changes: its new length, then the values).
seeded = recorded.get("seeded") or []
check(len(seeded) == 24, "the seed button called auto_widgets for 3 widgets")
check(len(states) > len(steps) and close(states[-1], seeded),
      "seed: GaussianWidgets = the 3 seeded widgets")
# Hiding remembers the opacity (-1: shown); undo forgets it again.
check(hidden_states == [[-1, 0.7], []],
      "GaussianWidgetsHidden: [-1, 0.7] on hide, [] after undo (%s)" % hidden_states)
finish("gui_editor")
