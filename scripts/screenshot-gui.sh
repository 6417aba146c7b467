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
# Xvfb picks a free display number itself (-displayfd) and reports it once it is ready.
numfile=$(mktemp)
Xvfb -displayfd 3 -screen 0 1600x1000x24 -noreset 3>"$numfile" >/dev/null 2>&1 &
xvfb=$!
pv=""
trap 'kill $pv $xvfb 2>/dev/null || true; rm -f "$numfile"' EXIT
for _ in $(seq 1 20); do
  [ -s "$numfile" ] && break
  sleep 0.5
done
display=":$(tr -dc 0-9 <"$numfile")"
[ "$display" != ":" ] || { echo "Xvfb did not start" >&2; exit 1; }
cd "$repo"
done_file=$(mktemp -u)
DISPLAY="$display" MCV_GUI_DONE="$done_file" PV_PLUGIN_PATH="$plugin" MCV_DATA_DIR="${MCV_DATA_DIR:-$repo/.cache/volumes}" \
  paraview --dr -geometry 1600x1000+0+0 --script="$repo/scripts/gui_loop_setup.py" \
  >/dev/null 2>&1 &
pv=$!
# The brain chain takes a while on a small machine, and the window is painted in part while
# it runs: wait until the setup script has shown everything (it writes $done_file), then
# until something is drawn (not one colour) and the picture stops changing.
previous=""
for i in $(seq 1 100); do
  sleep 5
  DISPLAY="$display" xwd -root -silent > /tmp/mcv_gui_loop.xwd
  now=$(md5sum < /tmp/mcv_gui_loop.xwd)
  spread=$(convert xwd:/tmp/mcv_gui_loop.xwd -format "%[fx:standard_deviation > 0.05]" info:)
  [ -e "$done_file" ] && [ "$spread" = 1 ] && [ -n "$previous" ] && [ "$now" = "$previous" ] &&
    break
  previous="$now"
done
mkdir -p "$repo/docs/images"
convert xwd:/tmp/mcv_gui_loop.xwd -resize 75% -strip "$repo/docs/images/gui_loop.png"
rm -f /tmp/mcv_gui_loop.xwd "$done_file"
echo "wrote $repo/docs/images/gui_loop.png"
