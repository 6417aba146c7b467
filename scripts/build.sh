#!/usr/bin/env bash
# Configures and builds the project into ./build (ParaView plugin, core, CUDA when nvcc is
# found, tests). Extra arguments go to the CMake configure step, e.g. -DMCV_ENABLE_CUDA=OFF.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MCV_BUILD_DIR:-$repo/build}"
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
# nvcc lives outside PATH on a default CUDA install.
if ! command -v nvcc >/dev/null 2>&1 && [ -x /usr/local/cuda/bin/nvcc ]; then
  export PATH="/usr/local/cuda/bin:$PATH"
fi
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$repo" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@"
elif [ "$#" -gt 0 ]; then
  cmake "$build" "$@"
fi
cmake --build "$build" -j "$(nproc)"
