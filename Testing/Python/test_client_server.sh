#!/bin/sh
# test_client_server.sh PVPYTHON PVSERVER MPIEXEC [PROCESSES...]: the exploration loop
# client-server (client_server_loop_check.py). A built-in pvpython run writes the reference
# answers; then, for each count in PROCESSES (default 2), a pvserver of that many
# processes (1: plain pvserver, more: under mpiexec) is started under its own virtual X server on a free port, pvpython connects to
# it, runs the same loop and compares every answer with the reference. The server is
# stopped after each run, also when the client fails or the test is interrupted.
# Exit 125 (skipped) when the data is missing.
set -u
pvpython="$1"
pvserver="$2"
mpiexec="$3"
shift 3
counts="${*:-2}"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/client_server_loop_$(echo "$counts" | tr " " "_")"
rm -rf "$out"
mkdir -p "$out"

# The plugin is loaded by the client script (LoadPlugin remote=True and remote=False, as a
# user does), not auto-loaded from PV_PLUGIN_PATH; MCV_PLUGIN names it.
unset PV_PLUGIN_PATH
sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_loop_check.py" --reference "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc

. "$here/pvserver_control.sh"

loop_client() {  # the loop in pvpython connected to the running server of $n processes
  sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_loop_check.py" \
    --compare "$out" --connect "$port" --processes "$n"
}
failed=0
for n in $counts; do
  run_on_server "$n" loop_client
  rc=$?
  [ $rc -eq 0 ] || failed=$rc
done

# The table: every check, built-in against each server (a run that stopped has no column).
echo "== the checks, built-in against pvserver with $counts processes"
/usr/bin/python3 "$here/client_server_table.py" "$out" || failed=1
[ $failed -eq 0 ] || exit $failed

# Bad input on a server of the first count's processes.
n=$(echo "$counts" | cut -d' ' -f1)
# A server without the plugin: the helpers say what is missing.
echo "== pvserver with $n processes, without the plugin"
start_server_retrying "$n" || exit 1
sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_loop_check.py" \
  --no-server-plugin --connect "$port"
rc=$?
stop_server
[ $rc -eq 0 ] || exit $rc

# A server process killed during an update: the client reports it, nothing hangs (the
# client is given 300 s; a hang ends as exit 124).
echo "== pvserver with $n processes, one killed during an update"
start_server_retrying "$n" || exit 1
marker="$out/updating"
rm -f "$marker"
timeout 300 sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_loop_check.py" \
  --server-dies "$marker" --connect "$port" &
client=$!
for _ in $(seq 1 240); do
  [ -e "$marker" ] && break
  kill -0 "$client" 2>/dev/null || break
  sleep 0.5
done
sleep 3
victim=$(server_process)
if [ -e "$marker" ] && [ -n "$victim" ]; then
  echo "killing pvserver process $victim during the update"
  kill -9 "$victim"
else
  echo "test_client_server.sh: the client did not reach the update (marker $marker)" >&2
fi
wait "$client"
rc=$?
stop_server
[ $rc -eq 124 ] && echo "test_client_server.sh: the client hung after the server died" >&2
exit $rc
