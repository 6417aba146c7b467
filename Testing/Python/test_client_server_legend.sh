#!/bin/sh
# test_client_server_legend.sh PVPYTHON PVSERVER MPIEXEC [PROCESSES]: the Gaussian widget
# legend in the picture (client_server_legend_check.py), first in a built-in pvpython
# session, then in pvpython connected to a pvserver of PROCESSES processes (default 2;
# under mpiexec when more than 1) started under its own virtual X server on a free port.
# The server is stopped after the run, also when the client fails or the test is
# interrupted. Exit 125 (skipped) when the data is missing.
set -u
pvpython="$1"
pvserver="$2"
mpiexec="$3"
n="${4:-2}"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/client_server_legend"
rm -rf "$out"
mkdir -p "$out"

# The plugin is loaded by the client script on both sides (remote=True, remote=False).
unset PV_PLUGIN_PATH
echo "== built-in session"
sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_legend_check.py" --out "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc

. "$here/pvserver_control.sh"

legend_client() {  # the check in pvpython connected to the running server
  sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_legend_check.py" \
    --out "$out" --connect "$port"
}
run_on_server "$n" legend_client
