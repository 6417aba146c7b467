"""GUI test of Probe, part 3 (run by test_gui.sh with the state file and paraview's exit
status): the click in the volume view probed the voxel seen at that pixel (the top voxel
of the column nearest to it), with its own ReducedCoordinates, and the marker moved there
in the domain view; a click on a domain point probed that point's voxel; Add Widget Here
put a widget there with an unused palette colour; a rubber band (Select Points Through) in the domain view, then Brush
Selection, highlighted exactly the voxels of the selected domain points."""

from gui_checks import arguments, check, fails, finish, recorded_events  # noqa: E402,F401

path, rc = arguments()


def close(a, b):
    return a is not None and b is not None and all(abs(x - y) < 1e-6 for x, y in zip(a, b))


events = recorded_events(path, rc)
probes = [e for e in events if e["event"] == "probe"]
if check(len(probes) == 1, "the click in the volume view probed once (%d)" % len(probes)):
    p = probes[0]
    check(p["point_id"] == p["expected_id"],
          "... the voxel seen at pixel %s of the %s view: id %s (expected %s)"
          % (p["pixel"], p["view_size"], p["point_id"], p["expected_id"]))
    check(close(p["coordinates"], p["expected_coordinates"]),
          "... its ReducedCoordinates %s" % p["coordinates"])
    check(close(p["marker"], p["expected_coordinates"]),
          "... the marker in the domain view at them (%s)" % p["marker"])
domain = [e for e in events if e["event"] == "probe_domain"]
if check(len(domain) == 1, "the click in the domain view probed once (%d)" % len(domain)):
    d = domain[0]
    check(d["expected_id"] is not None and d["point_id"] == d["expected_id"],
          "... the voxel of the cloud point at pixel %s: id %s (expected %s)"
          % (d["pixel"], d["point_id"], d["expected_id"]))
    check(close(d["marker"], d["coordinates"]) and probes and
          d["point_id"] != probes[0]["point_id"],
          "... another voxel than the volume's click, the marker moved to its coordinates %s"
          % d["coordinates"])
added = [e for e in events if e["event"] == "add_widget"]
if check(len(added) == 1, "Add Widget Here called add_widget_at once (%d)" % len(added)):
    a = added[0]
    used = [a["before"][i + 4:i + 7] for i in range(0, len(a["before"]), 8)]
    check(len(a["after"]) == len(a["before"]) + 8 and a["after"][-8:] == a["widget"] and
          domain and close(a["widget"][:3], domain[0]["coordinates"]),
          "... one widget appended at the domain probe's coordinates %s" % a["widget"][:3])
    check(any(close(a["widget"][4:7], c) for c in a["palette"]) and
          not any(close(a["widget"][4:7], u) for u in used) and a["widget"][7] == 0.5,
          "... a palette colour no widget had %s, opacity 0.5" % a["widget"][4:7])
brushes = [e for e in events if e["event"] == "brush"]
check(len(brushes) == 1, "Brush Selection after the rubber band called brush once (%d)"
      % len(brushes))
for b in brushes:
    check(b["expected"] and b["count"] == len(b["expected"]) and
          b["highlighted"] == b["expected"],
          "Brush Selection: the %d voxels of the selected domain points highlighted (%d)"
          % (len(b["expected"]), b["count"]))
finish("gui_probe")
