#!/usr/bin/env bash
# The main job alone, on a machine where the project is set up and built (run-main.sh does
# both first): pvbatch Examples/transfer_function.py with the plugin, under a virtual X
# server unless DISPLAY is set. Arguments go to transfer_function.py.
# pvbatch maps about 0.6 GiB of libraries before any script runs: under a smaller address-space
# limit (ulimit -v) the loader fails (exit 127) and the job could not say why, so a trial
# start comes first and turns that into the job's own "error: ... needs ... available" and
# exit code 1 (docs/reliability.md).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MCV_BUILD_DIR:-$repo/build}"
plugin="${MCV_PLUGIN:-$(find "$build" -name 'MultichannelExplorer.so' -print -quit 2>/dev/null)}"
[ -n "$plugin" ] && [ -f "$plugin" ] || { echo "error: the plugin is not built (run scripts/build.sh)"; exit 1; }
export MCV_DATA_DIR="${MCV_DATA_DIR:-$repo/.cache/volumes}"

trial="$(pvbatch --version 2>&1)" || {
  code=$?
  if [ "$code" = 127 ] && grep -q "error while loading shared libraries" <<<"$trial"; then
    limit="$(ulimit -v)"
    if [ "$limit" != unlimited ]; then
      available="$(awk -v k="$limit" 'BEGIN { printf "%.2f", k / 1048576 }')"
      echo "error: pvbatch cannot start: the job needs at least 1 GiB of address space, ulimit -v leaves ${available} GiB available (${trial##*: })"
    else
      echo "error: pvbatch cannot start: ${trial}"
    fi
  else
    echo "error: pvbatch cannot start (exit ${code}): ${trial}"
  fi
  exit 1
}

job=(pvbatch "$repo/Examples/transfer_function.py" --plugin "$plugin" "$@")
if [ -n "${DISPLAY:-}" ]; then
  exec "${job[@]}"
fi
# A free display from a random number, not always from :99 (as Testing/Python/run_pvbatch.sh).
exec xvfb-run -a -n $(( 100 + $(od -An -N2 -tu2 /dev/urandom) % 800 )) -s "-screen 0 1280x1024x24 -noreset" "${job[@]}"
