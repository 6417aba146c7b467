"""GUI test of a first exploration by clicks, part 3 (run by test_gui.sh with the state file
and paraview's exit status): the three files opened through the file dialog became one
exploration (the pipeline's pieces named after them), the volume and the reduced domain
side by side, widgets seeded, the camera at the best view, the drag moved one widget as
one named undo step, the probe answered, Add Widget Here was one named undo step, and
Edit > Undo took back the added widget, the drag, then the whole exploration in one
step."""
import math
import os
import sys

from gui_checks import arguments, check, finish, load_state

path, rc = arguments()
s = load_state(path)
if s.get("files") is not None and len(s.get("files", [])) < 3:
    print("SKIP: ch2, aal and brodmann are not all in MCV_DATA_DIR (%s)" % s.get("files"))
    sys.exit(125)
check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
e = s.get("explored")
if not check(e is not None, "Explore Multichannel ran to its end (steps: %s)" % s.get("steps")):
    finish("gui_explore")

name = "ch2 + aal + brodmann"
sources = e["snapshot"]["sources"]
check(e["name"] == name, "the exploration is named after the three files: %r" % e["name"])
readers = [n for n, v in sources.items() if not v["inputs"]]
check(sorted(readers) == ["aal.nii.gz", "brodmann.nii.gz", "ch2.nii.gz"],
      "the file dialog opened the three files as three readers: %s" % sorted(readers))
expected = {"Channels of " + name: "MergeChannels",
            "Exploration of " + name: "DimensionReduction",
            "Reduced domain of " + name: "ReducedDomain",
            "Widget spheres of " + name: "Glyph",
            "Best viewpoint of " + name: "BestViewpoint"}
for piece, kind in expected.items():
    check(sources.get(piece, {}).get("type") == kind,
          "the pipeline has %r, a %s (%s)" % (piece, kind, sources.get(piece)))
check(sorted(sources.get("Channels of " + name, {}).get("inputs", [])) == sorted(readers),
      "... the three readers merged")
check(sources.get("Exploration of " + name, {}).get("inputs") == ["Channels of " + name],
      "... the reduction on the merged channels")
check(e["active_source"] == "Exploration of " + name and e["volume_view_is_active"],
      "the reduction is the active source, its volume view the active view")

views = e["snapshot"]["views"]
render = [v for v in views if v["type"] == "RenderView"]
volume = [v for v in render if any(r["representation"] == "Gaussian TF Volume" and
                                   r["source"] == "Exploration of " + name for r in v["shown"])]
domain = [v for v in render if any(r["source"] == "Reduced domain of " + name
                                   for r in v["shown"])]
check(len(views) == 2 and len(render) == 2,
      "two views, both render views (no chart opened by itself): %s"
      % [v["type"] for v in views])
if check(len(volume) == 1 and len(domain) == 1 and volume[0] is not domain[0],
         "one view shows the volume as Gaussian TF Volume, the other the reduced domain"):
    check(volume[0]["layout"] is not None and volume[0]["layout"] == domain[0]["layout"] and
          volume[0]["cell"] != domain[0]["cell"],
          "... side by side in one layout (cells %s and %s)" % (volume[0]["cell"],
                                                                domain[0]["cell"]))
    check(any(r["source"] == "Widget spheres of " + name for r in domain[0]["shown"]),
          "... the widget spheres in the domain view")
    check([r["source"] for r in volume[0]["shown"]] == ["Exploration of " + name],
          "... and nothing else in the volume view (the readers hidden): %s"
          % volume[0]["shown"])
widgets = e["widgets"]
count = len(widgets) // 8
check(count >= 2 and len(widgets) % 8 == 0 and
      all(widgets[i + 3] > 0 for i in range(0, len(widgets), 8)),
      "widgets seeded: %d, every sigma > 0" % count)

if check(e["direction"] is not None, "the best view was found"):
    c = e["camera"]
    d = [f - p for f, p in zip(c["focal_point"], c["position"])]
    cos = sum(a * b for a, b in zip(d, e["direction"])) / math.sqrt(sum(a * a for a in d))
    check(cos > 0.9999, "the camera was turned to it: looks along the best direction "
          "(cos %.6f)" % cos)

pushed = [u["labels"][0] for u in s["undo"] if u["event"] == "pushed" and u["labels"]]
check("Explore Multichannel" in pushed,
      "one undo step named \"Explore Multichannel\" (pushed: %s)" % pushed)
# ParaView's own File > Open pushes "Changed 'vtkSMProxy'" steps with each reader (the
# plugin's code is not involved there); from the exploration on, every step is named.
ours = pushed[pushed.index("Explore Multichannel"):] if "Explore Multichannel" in pushed else []
check(ours and not any(label.startswith("Changed '") for label in ours),
      "no undo step named after a class from Explore Multichannel on: %s" % ours)
moves = [label for label in pushed if label.startswith("Move Gaussian Widget ")]
moved = after = None
if check(len(moves) == 1, "the drag is one undo step %s" % moves):
    moved = int(moves[0].split()[-1]) - 1
    # The widgets when the drag's undo set was pushed (the drag's last change).
    at_push = [u["changes_so_far"] for u in s["undo"] if u["event"] == "pushed" and
               u["labels"] and u["labels"][0] == moves[0]][0]
    after = s["changes"][at_push - 1] if at_push else widgets
    changed = [i // 8 for i in range(len(widgets)) if abs(after[i] - widgets[i]) > 1e-9]
    check(sorted(set(changed)) == [moved],
          "... it moved widget %d only (changed: %s)" % (moved + 1, sorted(set(changed))))
    check(all(abs(after[8 * moved + 3 + j] - widgets[8 * moved + 3 + j]) < 1e-12
              for j in range(5)),
          "... its centre only (sigma, colour, opacity kept)")

probes = s.get("probes", [])
check(len(probes) == 1 and probes[0]["point_id"] is not None,
      "the probe click in the volume view found a voxel: %s" % probes)

added = [label for label in pushed if label == "Add Gaussian Widget Here"]
check(len(added) == 1, "Add Widget Here after the probe: one undo step named after it (%s)"
      % pushed[-3:])
undone = [u for u in s["undo"] if u["event"] == "undone"]
if check(len(undone) == 3, "Edit > Undo ran three times (%d)" % len(undone)):
    added_undone, first, second = undone
    check(moved is not None and added_undone.get("widgets") == after,
          "the first Undo removed the added widget (the %d widgets as after the drag)" % count)
    check(first.get("widgets") == widgets,
          "the second Undo put the dragged widget back (all %d widgets as seeded)" % count)
    left = first["snapshot"]["sources"]
    check(all(piece in left for piece in expected), "... and kept the exploration")
    left = second["snapshot"]["sources"]
    check(sorted(left) == sorted(readers),
          "the third Undo removed the whole exploration in one step (left: %s)"
          % sorted(left))
    check(len(second["snapshot"]["views"]) == 1,
          "... and its domain view (%d views left)" % len(second["snapshot"]["views"]))
shot = s.get("screenshot")
check(shot and os.path.exists(shot) and os.path.getsize(shot) > 10000,
      "the whole window after the probe: %s" % shot)
finish("gui_explore")
