"""What every gui_NAME_check.py shares (plain python3, run by test_gui.sh with the state
file and paraview's exit status): the arguments, check() that prints and collects a
failure, and finish() that prints the count and exits 1 on any failure."""
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


def finish(name):
    print("%s: %d failed" % (name, len(fails)))
    sys.exit(1 if fails else 0)
