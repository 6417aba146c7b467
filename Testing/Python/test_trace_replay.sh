#!/bin/sh
# test_trace_replay.sh PVBATCH: a trace of the README workflow done with the Python helpers
# (trace_replay_check.py --record) replays in a fresh pvbatch without the plugin loaded
# (--replay: the trace loads it) to the recorded picture. Exit 125 (skipped) when the data
# is missing.
set -u
pvbatch="$1"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/trace_replay"
rm -rf "$out"
mkdir -p "$out"
sh "$here/run_pvbatch.sh" "$pvbatch" "$here/trace_replay_check.py" --record "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc
# The replay must not find the plugin on its own.
unset PV_PLUGIN_PATH MCV_PLUGIN
sh "$here/run_pvbatch.sh" "$pvbatch" "$here/trace_replay_check.py" --replay "$out"
