#!/bin/sh
# record_replay.sh PVBATCH CHECK [FILE...]: `pvbatch CHECK --record DIR` builds a scene with
# the plugin and writes what replays it (Python states, traces) and its picture into DIR
# (MCV_OUTPUT_DIR/<CHECK without .py>); then, in fresh pvbatch processes without the plugin
# loaded (no PV_PLUGIN_PATH, no MCV_PLUGIN: the replayed file must load it),
# `pvbatch CHECK --replay DIR FILE` for each FILE (`--replay DIR` once when none is given)
# checks the replay against the recording. Exit 125 (skipped) when the data is missing.
set -u
pvbatch="$1"
check="$2"
shift 2
. "$(dirname "$0")/pvbatch_runs.sh"
first_run_into "$pvbatch" "$check" --record
unset PV_PLUGIN_PATH MCV_PLUGIN
if [ $# -eq 0 ]; then
  sh "$here/run_pvbatch.sh" "$pvbatch" "$here/$check" --replay "$out"
  exit $?
fi
for file in "$@"; do
  sh "$here/run_pvbatch.sh" "$pvbatch" "$here/$check" --replay "$out" "$file" || exit $?
done
