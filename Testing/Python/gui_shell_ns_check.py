"""GUI test "the helpers in the GUI's Python shell, plugin loaded with ns=", part 3 (run by
test_gui.sh with the state file and paraview's exit status): the plugin was not
auto-loaded, LoadPlugin(..., ns=globals()) put its filters into the script's namespace, and
every helper called ran without an exception."""
from gui_checks import arguments, check, finish, load_state

path, rc = arguments()
state = load_state(path)
check(rc == 0, "paraview exited normally (%d)" % rc)
check(state.get("autoloaded") is False, "the plugin was not auto-loaded (no PV_PLUGIN_PATH)")
check(state.get("in_namespace"), "LoadPlugin(..., ns=globals()) put the filters in the namespace")
events = state.get("events", [])
for event in events:
    check(event["ok"], "%s: %s" % (event["step"], event.get("result") or event.get("error")))
check(len(events) == 13 and state.get("done"), "all 13 helpers were called (%d)" % len(events))
finish("gui_shell_ns")
