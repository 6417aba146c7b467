#!/usr/bin/env bash
# Copies the header-only libraries that the GPU machine lacks (nanoflann, Spectra) into
# .cache/include, which Testing/gpu/run-on-device.sh adds to CMake's include path there.
# Run here, then carry .cache/include (and .cache/volumes) with the device call.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dest="$repo/.cache/include"
mkdir -p "$dest"
cp /usr/include/nanoflann.hpp "$dest/"
cp -r /usr/include/Spectra "$dest/"
echo "prepare-device: headers in $dest"
