#!/bin/sh
# test_gui.sh PARAVIEW NAME: the plugin in the ParaView GUI. Loads it through
# PV_PLUGIN_PATH, runs gui_NAME_setup.py (opens data, wraps the Python helper the button
# calls so that what it does is recorded into $MCV_OUTPUT_DIR/gui_NAME_state.json), plays
# gui_NAME_click.xml (QtTesting: clicks toolbar buttons), exits, then checks the state file
# with gui_NAME_check.py STATE EXIT_STATUS.
# Env: MCV_DATA_DIR, MCV_OUTPUT_DIR, PV_PLUGIN_PATH (set by CTest). Exit 125: no data.
here=$(cd "$(dirname "$0")" && pwd)
paraview="$1"
name="$2"
[ -f "$MCV_DATA_DIR/brainsmall.den" ] || { echo "SKIP: no brainsmall.den"; exit 125; }
mkdir -p "$MCV_OUTPUT_DIR"
state="$MCV_OUTPUT_DIR/gui_${name}_state.json"
rm -f "$state"
export MCV_GUI_STATE="$state"
# The setup scripts import gui_setup.py and mcv_testing.py from here.
export PYTHONPATH="$here${PYTHONPATH:+:$PYTHONPATH}"
# --dr: default settings (no welcome dialog); a failed playback would wait on a dialog,
# hence the timeout (MCV_GUI_TIMEOUT seconds, default 300). --test-directory: $PARAVIEW_TEST_ROOT in a file dialog's playback.
# MCV_GUI_GEOMETRY (e.g. 1280x1000+0+0): the main window's size, for tests whose screenshot
# is shown in the documentation.
sh "$here/run_pvbatch.sh" timeout "${MCV_GUI_TIMEOUT:-300}" "$paraview" --dr --test-directory="$MCV_OUTPUT_DIR" \
  ${MCV_GUI_GEOMETRY:+-geometry "$MCV_GUI_GEOMETRY"} \
  --script="$here/gui_${name}_setup.py" \
  --test-script="$here/gui_${name}_click.xml" --exit
rc=$?
echo "paraview exit status: $rc"
exec python3 "$here/gui_${name}_check.py" "$state" "$rc"
