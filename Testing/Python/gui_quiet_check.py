"""GUI test "no noise for the expected case", part 3 (run by test_gui.sh with the state
file and paraview's exit status): the chain ran in the GUI with Device Auto, and not one
warning or error reached ParaView's output window (so the Output Messages window never
opened)."""
from gui_checks import arguments, check, fails, finish, load_state  # noqa: E402,F401

path, rc = arguments()
state = load_state(path)
print("state: %s" % state)
check(rc == 0, "paraview exited normally (%d)" % rc)
check(state.get("done"), "the chain ran to the end in the GUI: %s" % state.get("steps"))
check(state.get("output_window", "").startswith("pq") or state.get("output_window"),
      "observing ParaView's output window (%s)" % state.get("output_window"))
check(state.get("messages") == [], "no warning or error reached the output window: %s"
      % state.get("messages"))
finish("gui_quiet")
