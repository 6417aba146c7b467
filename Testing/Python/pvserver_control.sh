# pvserver_control.sh: sourced by the client-server tests (test_client_server.sh,
# test_client_server_legend.sh, test_gui_server.sh). Starts a pvserver under its own virtual X server on a free port and
# stops it again by process id, also after a failure or an interrupt. N > 1 processes run
# under mpiexec; N = 1 is a plain `pvserver`, as a user starts one without MPI.
#   start_server N             0 when the server of N processes accepts connections;
#                              sets $port, $server_pid, $xvfb_pid
#   server_process             the id of one pvserver process (the last of mpiexec's
#                              children; the server itself when it runs without mpiexec)
#   start_server_retrying N    start_server, 3 attempts (a port taken meanwhile)
#   stop_server                TERM, then KILL, to mpiexec and its pvservers; the X server
#   lost_display N             0 when the server of N processes stopped because it lost
#                              its X server ("bad X server connection", seen now and then
#                              on a loaded machine): a run worth retrying
#   run_on_server N CLIENT     start a server of N processes, run the shell function
#                              CLIENT (it reads $port), stop the server; once more when
#                              the server lost its X server; CLIENT's status; the
#                              server's log tail when CLIENT failed
# Needs $mpiexec, $pvserver and $out (where the logs go). Installs an EXIT/INT/TERM trap
# that stops the server.

# Open MPI refuses root and more processes than cores unless told (ignored by other MPIs).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
export OMP_NUM_THREADS=1

server_pid=""
xvfb_pid=""
port=""
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
      echo "pvserver_control.sh: server processes still running: $left" >&2
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

# A free TCP port (bound by the OS, released).
free_port() {
  /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])'
}

start_server() {  # start_server PROCESSES: 0 when the server accepts connections
  n="$1"
  # The X server is started on a display number of its own and says when it accepts
  # connections (-displayfd: the number, written to the descriptor once it does). A number
  # whose lock another test's X server holds makes this one exit ("Server is already
  # active"): the next number is tried. Checking a chosen number with xdpyinfo and starting
  # it after would not do: another test could take it in between, and the pvserver would
  # draw on a display that test stops. Numbers from 500 up, never :0: with the X server on
  # :0, a server of 4 MPI processes reported no remote rendering (every process had
  # OpenGL; 1 and 2 processes rendered), so the client drew the view without the volume.
  # -noreset: an X server resets when its last client leaves and hangs up on a connection
  # made meanwhile; a pvserver process closes its OpenGL check's connection and opens its
  # window's at once, so without it one process in a few got "bad X server connection"
  # (remote rendering not available, or the process aborted; strace: POLLHUP right after
  # the connection's first bytes).
  display=""
  first=$(( ($$ % 400) + 500 ))
  for candidate in $(seq "$first" $((first + 9))); do
    rm -f "$out/xvfb_$n.display"
    Xvfb ":$candidate" -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset \
      3>"$out/xvfb_$n.display" >"$out/xvfb_$n.log" 2>&1 &
    xvfb_pid=$!
    display=""
    for _ in $(seq 1 40); do
      display=$(tr -dc 0-9 <"$out/xvfb_$n.display" 2>/dev/null)
      [ -n "$display" ] && break
      kill -0 "$xvfb_pid" 2>/dev/null || break
      sleep 0.5
    done
    [ -n "$display" ] && kill -0 "$xvfb_pid" 2>/dev/null && break
    kill "$xvfb_pid" 2>/dev/null
    wait "$xvfb_pid" 2>/dev/null
    xvfb_pid=""
    display=""
  done
  if [ -z "$display" ] || ! kill -0 "$xvfb_pid" 2>/dev/null ||
     ! DISPLAY=":$display" xdpyinfo >/dev/null 2>&1; then
    echo "pvserver_control.sh: the X server did not start (display '$display'):" >&2
    cat "$out/xvfb_$n.log" >&2
    stop_server
    return 1
  fi
  port=$(free_port)
  if [ "$n" -eq 1 ]; then
    DISPLAY=":$display" "$pvserver" --server-port="$port" >"$out/pvserver_$n.log" 2>&1 &
  else
    DISPLAY=":$display" "$mpiexec" -n "$n" "$pvserver" --server-port="$port" \
      >"$out/pvserver_$n.log" 2>&1 &
  fi
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
  echo "pvserver_control.sh: pvserver on port $port did not start:" >&2
  cat "$out/pvserver_$n.log" >&2
  stop_server
  return 1
}

start_server_retrying() {  # start_server_retrying PROCESSES: 3 attempts
  # (sh has no local variables: names of its own, not the callers' loop variables)
  for _start_try in 1 2 3; do
    if start_server "$1"; then
      return 0
    fi
    echo "pvserver_control.sh: retrying the server start (attempt $_start_try)" >&2
  done
  return 1
}

lost_display() {  # lost_display PROCESSES: 0 when that server's log says its X server went
  # VTK's message when the display cannot be opened, and Xlib's when an open one breaks.
  grep -q -e "bad X server connection" -e "XIO: *fatal IO error" -e "X connection to .* broken" \
    "$out/pvserver_$1.log" 2>/dev/null
}

server_log_tail() {  # server_log_tail PROCESSES: why a server went away, for the test's log
  echo "pvserver_control.sh: the last lines of the server's log ($out/pvserver_$1.log):" >&2
  tail -n 25 "$out/pvserver_$1.log" >&2 2>/dev/null
  echo "pvserver_control.sh: the last lines of its X server's log:" >&2
  tail -n 5 "$out/xvfb_$1.log" >&2 2>/dev/null
}

server_process() {  # one pvserver process of the running server
  _child=$(pgrep -P "$server_pid" | tail -n 1)
  echo "${_child:-$server_pid}"
}

run_on_server() {  # run_on_server PROCESSES CLIENT: CLIENT's status (see the list above)
  for _server_try in 1 2; do
    echo "== pvserver with $1 processes"
    start_server_retrying "$1" || return 1
    "$2"
    _client_rc=$?
    stop_server
    [ $_client_rc -ne 0 ] && server_log_tail "$1"
    # A server that lost its X server (not a failure of the client) is tried once more.
    if [ $_client_rc -ne 0 ] && [ $_server_try -eq 1 ] && lost_display "$1"; then
      echo "pvserver_control.sh: the pvserver lost its X server (bad X server connection): trying once more" >&2
      continue
    fi
    break
  done
  return $_client_rc
}
