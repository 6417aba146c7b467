#!/bin/sh
# Refreshes docs/images/gui_loop.png, the README's picture of the whole loop in the ParaView
# GUI (scripts/gui_loop_setup.py: the real brain as a Gaussian TF Volume, its reduced domain
# with the widget handles beside it, the widget editor, a probed voxel). Needs a build
# (MCV_BUILD_DIR, default ./build), the fetched volumes, Xvfb, xwd and ImageMagick.
set -eu
repo="$(cd "$(dirname "$0")/.." && pwd)"
build="${MCV_BUILD_DIR:-$repo/build}"
plugin="$build/lib/paraview-5.11/plugins/MultichannelExplorer"
[ -f "$plugin/MultichannelExplorer.so" ] || { echo "no plugin in $plugin: build first" >&2; exit 1; }
display=":$(( 100 + $(od -An -N2 -tu2 /dev/urandom) % 800 ))"
Xvfb "$display" -screen 0 1600x1000x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $pv $xvfb 2>/dev/null || true' EXIT
sleep 2
cd "$repo"
DISPLAY="$display" PV_PLUGIN_PATH="$plugin" MCV_DATA_DIR="${MCV_DATA_DIR:-$repo/.cache/volumes}" \
  paraview --dr -geometry 1600x1000+0+0 --script="$repo/scripts/gui_loop_setup.py" \
  >/dev/null 2>&1 &
pv=$!
# The brain chain takes a while on a small machine: wait until the picture stops changing.
previous=""
for i in $(seq 1 60); do
  sleep 5
  DISPLAY="$display" xwd -root -silent > /tmp/mcv_gui_loop.xwd
  now=$(md5sum < /tmp/mcv_gui_loop.xwd)
  [ -n "$previous" ] && [ "$now" = "$previous" ] && [ "$i" -gt 6 ] && break
  previous="$now"
done
mkdir -p "$repo/docs/images"
convert xwd:/tmp/mcv_gui_loop.xwd -resize 75% -strip "$repo/docs/images/gui_loop.png"
rm -f /tmp/mcv_gui_loop.xwd
echo "wrote $repo/docs/images/gui_loop.png"
