#!/usr/bin/env bash
# All tests from a fresh Debian 12 machine: installs what is missing, fetches the real
# volumes, builds, runs CTest (unit tests, pvbatch tests under xvfb-run; GPU tests skip
# where no GPU is usable) and prints CTest's summary line.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MCV_BUILD_DIR:-$repo/build}"
bash "$repo/scripts/setup.sh"
bash "$repo/scripts/build.sh"
cd "$build"
ctest --output-on-failure -j "$(nproc)" --timeout 900
