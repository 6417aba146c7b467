#!/bin/sh
# Refreshes docs/images/gui_editor.png, docs/gui.md's picture of the Gaussian widget editor:
# ParaView under a virtual X server plays the GUI test's edits (Testing/Python/
# gui_editor_{setup.py,click.xml}), the setup script takes a screenshot of the screen after
# the last edit, and this script crops it to the Properties panel.
# Needs a build (MCV_BUILD_DIR, default ./build), xvfb-run, xwd and ImageMagick's convert.
set -eu
repo="$(cd "$(dirname "$0")/.." && pwd)"
build="${MCV_BUILD_DIR:-$repo/build}"
plugin="$build/lib/paraview-5.11/plugins/MultichannelExplorer"
if [ ! -f "$plugin/MultichannelExplorer.so" ]; then
  echo "no plugin in $plugin: build first" >&2
  exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The setup script sizes the window to 1600x1000 at the origin and widens the left docks;
# the crop below (MCV_CROP overrides it) is the Properties panel in that layout.
PV_PLUGIN_PATH="$plugin" MCV_OUTPUT_DIR="$tmp" MCV_EDITOR_SCREENSHOT="$tmp/screen.png" \
  xvfb-run -a -s "-screen 0 1600x1000x24" timeout 150 paraview --dr -geometry 470x550+0+440 \
  --script="$repo/Testing/Python/gui_editor_setup.py" \
  --test-script="$repo/Testing/Python/gui_editor_click.xml" --exit || true
[ -f "$tmp/screen.png" ] || { echo "no screenshot was taken" >&2; exit 1; }
mkdir -p "$repo/docs/images"
convert "$tmp/screen.png" -crop "${MCV_CROP:-470x550+0+440}" +repage -strip \
  "$repo/docs/images/gui_editor.png"
echo "wrote $repo/docs/images/gui_editor.png"
