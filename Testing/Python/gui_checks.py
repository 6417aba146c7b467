"""What every gui_NAME_check.py shares (plain python3, run by test_gui.sh with the state
file and paraview's exit status): the arguments, check() that prints and collects a
failure, and finish() that prints the count and exits 1 on any failure."""
import json
import sys

fails = []


def arguments():
    """(state file path, paraview's exit status)."""
    return sys.argv[1], int(sys.argv[2])


def check(ok, msg):
    print(("ok   " if ok else "FAIL ") + msg)
    if not ok:
        fails.append(msg)
    return ok  # the "..." checks that follow a check run only when it passed


def recorded_events(path, rc):
    """Checks paraview's exit status and returns the events its setup script recorded into
    the state file (a failed check when the file cannot be read)."""
    check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
    try:
        with open(path) as f:
            return json.load(f)["events"]
    except Exception as e:  # noqa: BLE001
        check(False, "state file %s readable (%s)" % (path, e))
        return []


def load_state(path):
    """The state file the setup script wrote ({} with a failed check when unreadable)."""
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        check(False, "state file %s readable (%s)" % (path, e))
        return {}


def state_with_data(path, rc, data):
    """load_state(path) after paraview's exit status is checked; exits 125 (CTest's skip)
    when the setup script found its data file `data` missing (gui_setup.open_active)."""
    s = load_state(path)
    if s.get("data") is False:
        print("SKIP: %s is not in MCV_DATA_DIR" % data)
        sys.exit(125)
    check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
    return s


def finish(name):
    print("%s: %d failed" % (name, len(fails)))
    sys.exit(1 if fails else 0)
