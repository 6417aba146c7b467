"""GUI test of the loop connected to a pvserver, part 3 (run by test_gui_server.sh with
both sessions' state files and paraview's exit statuses):

- each session passes gui_probe_check.py (the probe in the volume view hit the voxel seen
  at that pixel, the domain probe its cloud point's voxel, Add Widget Here appended a
  widget there, Brush Selection highlighted exactly the selected domain points' voxels);
- the connected session was remote, on the expected number of server processes, with the
  plugin loaded on the client and on the server;
- the editor's edit set widget 1's peak opacity to 0.8 and nothing else; the handle drag
  moved widget 1's centre (right and down: +x, -y in the domain view looking down -z)
  and nothing else; Edit > Undo put the widgets back as before the drag;
- every answer of the connected session equals the built-in one: the probed voxels and
  their coordinates, the added widget, the brushed voxels, every widget change.

  python3 gui_server_check.py BUILTIN_STATE RC SERVER_STATE RC PROCESSES"""
import os
import subprocess
import sys

from gui_checks import check, finish, load_state
from mcv_testing import close

builtin_path, builtin_rc, server_path, server_rc, processes = (
    sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), int(sys.argv[5]))
here = os.path.dirname(os.path.abspath(__file__))


sessions = {}
for name, path, rc in (("built-in", builtin_path, builtin_rc),
                       ("connected", server_path, server_rc)):
    print("== %s session: gui_probe_check.py" % name)
    sys.stdout.flush()
    probe_rc = subprocess.call([sys.executable, os.path.join(here, "gui_probe_check.py"),
                                path, str(rc)])
    check(probe_rc == 0, "%s: Probe, Add Widget Here and Brush Selection give the data's "
          "answers (gui_probe_check.py)" % name)
    sessions[name] = load_state(path)

print("== the sessions")
b, s = sessions["built-in"], sessions["connected"]
session = s.get("session", {})
check(session.get("remote") is True and session.get("server_processes") == processes and
      session.get("plugin_on_client") and session.get("plugin_on_server"),
      "connected: a remote session (%s) of %s server processes (expected %d), the plugin on "
      "the client (%s) and on the server (%s)"
      % (session.get("uri"), session.get("server_processes"), processes,
         session.get("plugin_on_client"), session.get("plugin_on_server")))
check(b.get("session", {}).get("remote") is False, "built-in: not remote")

for name, st in (("built-in", b), ("connected", s)):
    initial = st.get("initial_widgets", [])
    changes = [c["values"] for c in st.get("widget_changes", [])]
    if not check(len(changes) >= 4, "%s: the widgets changed %d times (editor, Add Widget "
                 "Here, drag, undo: at least 4)" % (name, len(changes))):
        continue
    edited = changes[0]
    check(len(edited) == len(initial) == 8 and edited[7] == 0.8 and
          edited[:7] == initial[:7],
          "%s: the editor set widget 1's peak opacity to 0.8, nothing else (%s)"
          % (name, edited))
    added = changes[1]
    check(len(added) == 16 and added[:8] == edited,
          "%s: Add Widget Here appended widget 2 %s" % (name, added[8:]))
    # The press at the added widget's pixel lies inside widget 1's sphere too (sigma 50:
    # it encloses the view), whose handle takes the drag: widget 1's centre moves.
    dragged = [c for c in changes[2:] if len(c) == 16 and c != added]
    if check(len(dragged) >= 1, "%s: the handle drag changed the widgets (%d changes)"
             % (name, len(dragged))):
        end = dragged[-1]
        moved = [i for i in range(16) if abs(end[i] - added[i]) > 1e-9]
        check(moved and set(moved) <= {0, 1} and end[0] > added[0] and end[1] < added[1],
              "%s: the drag moved widget 1's centre right and down in the domain view, "
              "nothing else (%s -> %s)" % (name, added[0:2], end[0:2]))
    check(close(changes[-1], added, 1e-9, relative=False),
          "%s: Edit > Undo put the widgets back as before the drag" % name)

events = lambda st, kind: [e for e in st.get("events", []) if e["event"] == kind]  # noqa: E731
for kind, keys in (("probe", ("point_id", "coordinates", "marker")),
                   ("probe_domain", ("point_id", "coordinates", "marker")),
                   ("add_widget", ("widget", "after")),
                   ("brush", ("count", "highlighted"))):
    eb, es = events(b, kind), events(s, kind)
    same = len(eb) == len(es) and len(eb) > 0 and all(
        close([x[k] for k in keys], [y[k] for k in keys], 1e-6, relative=False)
        for x, y in zip(eb, es))
    check(same, "connected = built-in: %s (%s)" % (kind, ", ".join(
        "%s %s" % (k, es[0][k] if es and k != "after" else "") for k in keys[:2])))
check(close([c["values"] for c in s.get("widget_changes", [])],
            [c["values"] for c in b.get("widget_changes", [])], 1e-6, relative=False),
      "connected = built-in: every widget change (%d)" % len(s.get("widget_changes", [])))
finish("gui_server")
