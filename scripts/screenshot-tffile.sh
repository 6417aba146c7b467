#!/bin/sh
# Refreshes docs/images/gui_transfer_function_files.png, the docs' picture of the Gaussian
# widget editor's Save... and Load... buttons: ParaView under a virtual X server plays the
# GUI test (Testing/Python/gui_tffile_{setup.py,click.xml}: save, add, load), the setup
# script takes a screenshot of the screen after the load, and this script crops it to the
# Properties panel. Needs a build (MCV_BUILD_DIR, default ./build), the real volumes
# (MCV_DATA_DIR, default ./.cache/volumes), xvfb-run, xdotool, xwd and ImageMagick's convert.
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
PV_PLUGIN_PATH="$plugin" MCV_OUTPUT_DIR="$tmp" MCV_TFFILE_SCREENSHOT="$tmp/screen.png" \
  MCV_DATA_DIR="${MCV_DATA_DIR:-$repo/.cache/volumes}" \
  xvfb-run -a -s "-screen 0 1600x1000x24" timeout 200 paraview --dr \
  --test-directory="$tmp" \
  --script="$repo/Testing/Python/gui_tffile_setup.py" \
  --test-script="$repo/Testing/Python/gui_tffile_click.xml" --exit || true
[ -f "$tmp/screen.png" ] || { echo "no screenshot was taken" >&2; exit 1; }
mkdir -p "$repo/docs/images"
if [ -n "${MCV_CROP:-}" ]; then
  convert "$tmp/screen.png" -crop "$MCV_CROP" +repage -strip \
    "$repo/docs/images/gui_transfer_function_files.png"
else
  convert "$tmp/screen.png" -resize 1200x -strip \
    "$repo/docs/images/gui_transfer_function_files.png"
fi
echo "wrote $repo/docs/images/gui_transfer_function_files.png"
