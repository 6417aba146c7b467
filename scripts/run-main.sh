#!/usr/bin/env bash
# The main job from a fresh Debian 12 machine: installs what is missing, fetches the real
# volumes, builds, then runs the best viewpoint on the Colin27 brain (mricron-data) under
# pvbatch and writes best- and worst-view images and a JSON report into
# ./output/best_viewpoint. Arguments go to Examples/best_viewpoint.py: [VOLUME] [OUTPUT_DIR].
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MCV_BUILD_DIR:-$repo/build}"
bash "$repo/scripts/setup.sh"
bash "$repo/scripts/build.sh"
plugin="$(find "$build" -name 'MultichannelExplorer.so' -print -quit)"
[ -n "$plugin" ] || { echo "run-main: plugin not built" >&2; exit 1; }
data="${MCV_DATA_DIR:-$repo/.cache/volumes}"
args=("$@")
[ "${#args[@]}" -gt 0 ] || args=("$data/ch2.nii.gz" "$repo/output/best_viewpoint")
exec xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch "$repo/Examples/best_viewpoint.py" \
  --plugin "$plugin" "${args[@]}"
