#!/bin/sh
# test_state_replay.sh PVBATCH: Python state files (mce.save_state and ParaView's own
# smstate) and a trace of a scene of the plugin (state_replay_check.py --record) each load
# the plugin themselves and give the recorded display (hidden widgets, blend,
# classification) and picture in a fresh pvbatch without the plugin loaded (--replay).
set -u
pvbatch="$1"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/state_replay"
rm -rf "$out"
mkdir -p "$out"
sh "$here/run_pvbatch.sh" "$pvbatch" "$here/state_replay_check.py" --record "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc
# The replays must not find the plugin on their own.
unset PV_PLUGIN_PATH MCV_PLUGIN
for file in state.py smstate.py trace.py; do
  sh "$here/run_pvbatch.sh" "$pvbatch" "$here/state_replay_check.py" --replay "$out" "$file"
  rc=$?
  [ $rc -eq 0 ] || exit $rc
done
