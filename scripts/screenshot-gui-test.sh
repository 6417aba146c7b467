#!/bin/sh
# screenshot-gui-test.sh NAME IMAGE [CONVERT OPTIONS...]: refreshes docs/images/IMAGE from a
# GUI test's screenshot. ParaView under a virtual X server (1600x1000) plays the test
# (Testing/Python/gui_NAME_{setup.py,click.xml}); its setup script places the window at
# the origin, widens the left docks and saves the screen to $MCV_GUI_SCREENSHOT; ImageMagick's
# convert writes it with CONVERT OPTIONS. The pictures of the docs:
#   scripts/screenshot-gui-test.sh editor gui_editor.png -crop 470x550+0+440 +repage
#       docs/gui.md's Gaussian widget editor (the Properties panel after the last edit)
#   scripts/screenshot-gui-test.sh tffile gui_transfer_function_files.png -resize 1200x
#       docs/your-own-data.md's Save... and Load... buttons (the screen after the load)
# Needs a build (MCV_BUILD_DIR, default ./build), the real volumes (MCV_DATA_DIR, default
# ./.cache/volumes), xvfb-run, xdotool, xwd and ImageMagick's convert.
set -eu
[ $# -ge 2 ] || { sed -n '2,12p' "$0" >&2; exit 2; }
name="$1"
image="$2"
shift 2
repo="$(cd "$(dirname "$0")/.." && pwd)"
build="${MCV_BUILD_DIR:-$repo/build}"
plugin="$build/lib/paraview-5.11/plugins/MultichannelExplorer"
tests="$repo/Testing/Python"
if [ ! -f "$plugin/MultichannelExplorer.so" ]; then
  echo "no plugin in $plugin: build first" >&2
  exit 1
fi
if [ ! -f "$tests/gui_${name}_setup.py" ]; then
  echo "no GUI test $tests/gui_${name}_setup.py" >&2
  exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
PV_PLUGIN_PATH="$plugin" MCV_OUTPUT_DIR="$tmp" MCV_GUI_SCREENSHOT="$tmp/screen.png" \
  MCV_DATA_DIR="${MCV_DATA_DIR:-$repo/.cache/volumes}" \
  PYTHONPATH="$tests${PYTHONPATH:+:$PYTHONPATH}" \
  xvfb-run -a -s "-screen 0 1600x1000x24 -noreset" timeout 200 paraview --dr --test-directory="$tmp" \
  --script="$tests/gui_${name}_setup.py" --test-script="$tests/gui_${name}_click.xml" --exit ||
  true
[ -f "$tmp/screen.png" ] || { echo "no screenshot was taken" >&2; exit 1; }
mkdir -p "$repo/docs/images"
convert "$tmp/screen.png" "$@" -strip "$repo/docs/images/$image"
echo "wrote $repo/docs/images/$image"
