#!/bin/sh
# test_client_server.sh PVPYTHON PVSERVER MPIEXEC [PROCESSES...]: the exploration loop
# client-server (client_server_loop_check.py). A built-in pvpython run writes the reference
# answers; then, for each count in PROCESSES (default 2), an MPI pvserver of that many
# processes is started under its own virtual X server on a free port, pvpython connects to
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
out="${MCV_OUTPUT_DIR:-/tmp}/client_server_loop"
rm -rf "$out"
mkdir -p "$out"

# The plugin is loaded by the client script (LoadPlugin remote=True and remote=False, as a
# user does), not auto-loaded from PV_PLUGIN_PATH; MCV_PLUGIN names it.
unset PV_PLUGIN_PATH
sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_loop_check.py" --reference "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc

# Open MPI refuses root and more processes than cores unless told (ignored by other MPIs).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
export OMP_NUM_THREADS=1

server_pid=""
xvfb_pid=""
alive() {  # alive PID...: the ids among them of processes still running (not zombies)
  for p in "$@"; do
    state=$(ps -o stat= -p "$p" 2>/dev/null)
    case "$state" in
      ""|Z*) ;;
      *) echo "$p" ;;
    esac
  done
}
stop_server() {
  # The server's processes by id: TERM to mpiexec, which passes it on to its children (the
  # pvservers) and reaps them; after 10 s TERM to the children left, then KILL to all.
  # A process left over is reported. Then the X server.
  if [ -n "$server_pid" ]; then
    procs="$(pgrep -P "$server_pid" 2>/dev/null) $server_pid"
    kill "$server_pid" 2>/dev/null
    for _ in $(seq 1 20); do
      [ -z "$(alive $procs)" ] && break
      sleep 0.5
    done
    left=$(alive $procs)
    if [ -n "$left" ]; then
      kill $left 2>/dev/null
      sleep 2
    fi
    left=$(alive $procs)
    if [ -n "$left" ]; then
      kill -9 $left 2>/dev/null
      sleep 1
    fi
    wait "$server_pid" 2>/dev/null
    left=$(alive $procs)
    if [ -n "$left" ]; then
      echo "test_client_server.sh: server processes still running: $left" >&2
    fi
  fi
  if [ -n "$xvfb_pid" ]; then
    kill "$xvfb_pid" 2>/dev/null
    wait "$xvfb_pid" 2>/dev/null
  fi
  server_pid=""
  xvfb_pid=""
}
trap 'stop_server' EXIT
trap 'stop_server; exit 130' INT TERM

# A free display number (no lock file) and a free TCP port (bound by the OS, released).
free_display() {
  while :; do
    d=$(( 200 + $(od -An -N2 -tu2 /dev/urandom) % 700 ))
    [ -e "/tmp/.X$d-lock" ] || { echo "$d"; return; }
  done
}
free_port() {
  /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])'
}

start_server() {  # start_server PROCESSES: 0 when the server accepts connections
  n="$1"
  display=$(free_display)
  Xvfb ":$display" -screen 0 1280x1024x24 -nolisten tcp >"$out/xvfb_$n.log" 2>&1 &
  xvfb_pid=$!
  sleep 1
  port=$(free_port)
  DISPLAY=":$display" "$mpiexec" -n "$n" "$pvserver" --server-port="$port" \
    >"$out/pvserver_$n.log" 2>&1 &
  server_pid=$!
  for _ in $(seq 1 120); do
    if grep -q "Accepting connection" "$out/pvserver_$n.log" 2>/dev/null; then
      return 0
    fi
    if ! kill -0 "$server_pid" 2>/dev/null; then
      break  # it died (a port taken in the meantime, an X server that did not start)
    fi
    sleep 0.5
  done
  echo "test_client_server.sh: pvserver on port $port did not start:" >&2
  cat "$out/pvserver_$n.log" >&2
  stop_server
  return 1
}

for n in $counts; do
  echo "== pvserver with $n processes"
  started=0
  for attempt in 1 2 3; do
    if start_server "$n"; then
      started=1
      break
    fi
    echo "test_client_server.sh: retrying the server start (attempt $attempt)" >&2
  done
  [ $started -eq 1 ] || exit 1
  sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_loop_check.py" \
    --compare "$out" --connect "$port" --processes "$n"
  rc=$?
  stop_server
  [ $rc -eq 0 ] || exit $rc
done

# A server without the plugin: the helpers say what is missing.
echo "== pvserver with 2 processes, without the plugin"
started=0
for attempt in 1 2 3; do
  if start_server 2; then
    started=1
    break
  fi
done
[ $started -eq 1 ] || exit 1
sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_loop_check.py" \
  --no-server-plugin --connect "$port"
rc=$?
stop_server
[ $rc -eq 0 ] || exit $rc

# A server process killed during an update: the client reports it, nothing hangs (the
# client is given 300 s; a hang ends as exit 124).
echo "== pvserver with 2 processes, one killed during an update"
started=0
for attempt in 1 2 3; do
  if start_server 2; then
    started=1
    break
  fi
done
[ $started -eq 1 ] || exit 1
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
victim=$(pgrep -P "$server_pid" | tail -n 1)
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
