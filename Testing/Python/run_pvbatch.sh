#!/bin/sh
# run_pvbatch.sh PROGRAM [ARGS...]: runs pvbatch (or paraview) under a virtual X server.
# Debian's pvbatch aborts without a display. `xvfb-run -a` picks a free display number,
# but two runs started at the same moment (other test suites on the machine) can race for
# it; such a start-up failure, or a server lost before the first window opens (never a test
# failure), is retried up to 3 times.
pvbatch="$1"
shift
if ! command -v xvfb-run >/dev/null 2>&1; then
  if [ -n "$DISPLAY" ]; then exec "$pvbatch" "$@"; fi
  echo "xvfb-run not found and no DISPLAY: install xvfb" >&2
  exit 1
fi
log=$(mktemp "${TMPDIR:-/tmp}/mcv_pvbatch.XXXXXX")
trap 'rm -f "$log"' EXIT
attempt=1
while :; do
  # -a from a random display number, not always from :99: a server that has just exited
  # on :99 (the previous test's) is then not the one the next run starts over. -noreset:
  # the X server stays up between pvbatch's OpenGL check and its first window (a server
  # that resets when its last client leaves hangs up on a connection made meanwhile).
  xvfb-run -a -n $(( 100 + $(od -An -N2 -tu2 /dev/urandom) % 800 )) \
    -s "-screen 0 1280x1024x24 -noreset" "$pvbatch" "$@" >"$log" 2>&1
  rc=$?
  if [ $rc -ne 0 ] && [ $attempt -lt 3 ] &&
     grep -q -E "bad X server connection|Xvfb failed to start|Can't open display|cannot open display" "$log"; then
    echo "run_pvbatch.sh: X server start-up failed (attempt $attempt), retrying" >&2
    attempt=$((attempt + 1))
    sleep $attempt
    continue
  fi
  cat "$log"
  exit $rc
done
