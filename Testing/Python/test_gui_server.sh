#!/bin/sh
# test_gui_server.sh PARAVIEW PVSERVER MPIEXEC [PROCESSES]: the exploration loop in the
# ParaView GUI connected to an MPI pvserver. The same GUI test (gui_server_setup.py, events
# gui_server_click.xml: the editor, Probe, Add Widget Here, Brush Selection, a handle drag,
# undo) runs twice: built-in, then with `paraview --server-url=cs://localhost:PORT` against
# `mpiexec -n PROCESSES pvserver` (default 2) started on a free port under its own virtual X
# server and stopped afterwards (also after a failure or an interrupt). The plugin is
# auto-loaded on both sides (PV_PLUGIN_PATH, which the server inherits). Then
# gui_server_check.py checks both sessions' answers against the data and each other.
# Env: MCV_OUTPUT_DIR, PV_PLUGIN_PATH (set by CTest).
set -u
paraview="$1"
pvserver="$2"
mpiexec="$3"
processes="${4:-2}"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/gui_server"
rm -rf "$out"
mkdir -p "$out/builtin" "$out/server"
export MCV_TESTING_DIR="$here"
# The setup scripts import gui_setup.py from here.
export PYTHONPATH="$here${PYTHONPATH:+:$PYTHONPATH}"
[ -n "${PV_PLUGIN_PATH:-}" ] || { echo "test_gui_server.sh: PV_PLUGIN_PATH is not set" >&2; exit 1; }

run_gui() {  # run_gui DIR [PARAVIEW OPTIONS...]: the GUI test, its state in DIR/state.json
  dir="$1"
  shift
  MCV_OUTPUT_DIR="$dir" MCV_GUI_STATE="$dir/state.json" \
    sh "$here/run_pvbatch.sh" timeout 300 "$paraview" --dr --test-directory="$dir" "$@" \
    --script="$here/gui_server_setup.py" --test-script="$here/gui_server_click.xml" --exit \
    >"$dir/paraview.log" 2>&1
  rc=$?
  echo "paraview exit status: $rc ($dir)"
  return $rc
}

echo "== built-in"
run_gui "$out/builtin"
rc_builtin=$?

. "$here/pvserver_control.sh"
connected_gui() {  # the GUI test against the running server (run_on_server's client)
  grep -i "plugin" "$out/pvserver_$processes.log"
  rm -f "$out/server/state.json"
  run_gui "$out/server" --server-url="cs://localhost:$port"
}
echo "== connected to a pvserver of $processes processes"
run_on_server "$processes" connected_gui
rc_server=$?
/usr/bin/python3 "$here/gui_server_check.py" "$out/builtin/state.json" "$rc_builtin" \
  "$out/server/state.json" "$rc_server" "$processes"
