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

for attempt in 1 2; do
  echo "== pvserver with $n processes"
  start_server_retrying "$n" || exit 1
  sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_legend_check.py" \
    --out "$out" --connect "$port"
  rc=$?
  stop_server
  # A server that lost its X server (not a failure of the check) is tried once more.
  if [ $rc -ne 0 ] && [ $attempt -eq 1 ] && lost_display "$n"; then
    echo "test_client_server_legend.sh: the pvserver lost its X server: trying once more"
    continue
  fi
  break
done
exit $rc
