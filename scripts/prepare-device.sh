#!/usr/bin/env bash
# Copies the header-only libraries that the GPU machine lacks (nanoflann, Spectra, the
# Boost.Graph headers of Isomap's Dijkstra) into
# .cache/include, which Testing/gpu/run-on-device.sh adds to CMake's include path there.
# Run here, then carry .cache/include (and .cache/volumes) with the device call.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dest="$repo/.cache/include"
mkdir -p "$dest"
cp /usr/include/nanoflann.hpp "$dest/"
cp -r /usr/include/Spectra "$dest/"
# Boost.Graph's Dijkstra (IsomapEmbedding.cpp): only the headers it includes (~8 MB of
# Boost's 160), listed by the compiler.
printf '#include <boost/graph/compressed_sparse_row_graph.hpp>\n#include <boost/graph/dijkstra_shortest_paths_no_color_map.hpp>\n' |
  g++ -std=c++17 -M -x c++ - | tr ' \\' '\n\n' | grep '^/usr/include/boost/' | sort -u |
  while read -r h; do mkdir -p "$dest/$(dirname "${h#/usr/include/}")" && cp "$h" "$dest/${h#/usr/include/}"; done
echo "prepare-device: headers in $dest"
