#!/usr/bin/env bash
# One-time set-up of a fresh Debian 12 machine for this project (idempotent).
#   1. apt-installs the packages that are missing (checked with dpkg -s first, so a
#      second run is quick and needs no network);
#   2. fetches the real test volumes (scripts/fetch-data.sh) into <repo>/.cache/volumes.
# Runs as root, or through sudo when available.
#   MCV_SKIP_DATA=1     skip step 2
#   MCV_REQUIRE_DATA=1  fail when a volume cannot be fetched (default: warn and go on)
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  SUDO=()
fi

# ParaView 5.11 plugin build (see the notes: paraview-dev alone does not configure) ...
packages=(
  paraview paraview-dev python3-paraview libeigen3-dev xvfb qtbase5-dev libqt5svg5-dev
  qttools5-dev libqt5x11extras5-dev libutfcpp-dev qtxmlpatterns5-dev-tools libqt5opengl5-dev
  libhdf5-openmpi-dev libopenmpi-dev openmpi-bin libboost-dev libexpat1-dev libavcodec-dev
  libavformat-dev libavutil-dev libswscale-dev libfreetype-dev libgdal-dev libgl2ps-dev
  libglew-dev libjpeg-dev liblz4-dev liblzma-dev libxml2-dev libnetcdf-dev libgl-dev
  libpng-dev libtheora-dev libogg-dev libtiff-dev libx11-dev libxt-dev zlib1g-dev
  libdouble-conversion-dev python3-mpi4py python3-dev libpugixml-dev libjsoncpp-dev
  libfmt-dev libcgns-dev libprotobuf-dev libsqlite3-dev libproj-dev
  # ... and the core, its tests, benchmarks and the data fetch.
  xvfb xauth libgtest-dev googletest libbenchmark-dev ninja-build cmake g++ make
  python3-numpy
  # GUI tests and screenshot scripts: xwd (x11-apps), ImageMagick's convert, xdotool;
  # client-server tests: xdpyinfo (x11-utils) checks the X server before a pvserver starts.
  x11-apps imagemagick xdotool x11-utils
  # Microscopy formats: the tests write ImageJ hyperstacks, OME-TIFF and OME-Zarr with
  # tifffile and zarr; the OME-Zarr reader decodes Blosc chunks with libblosc.
  python3-tifffile python3-zarr python3-numcodecs libblosc-dev
  # The main job's spectrum.png and methods.png (Examples/report_figures.py).
  python3-matplotlib
  # Dimensionality reduction: kNN (nanoflann), sparse eigensolver (Spectra), Isomap's
  # Dijkstras (Boost.Graph, header-only, in libboost-dev), and scikit-learn and umap-learn
  # (UMAP's peer; pulls pynndescent and numba) as the references the comparison script
  # measures against (benchmarks only: no test needs them).
  libnanoflann-dev libspectra-dev libboost-dev python3-sklearn umap-learn
)
# Never libvtk9-dev: it pulls python3-vtk9, which conflicts with python3-paraview.

missing=()
declare -A seen=()
for p in "${packages[@]}"; do
  [ -n "${seen[$p]:-}" ] && continue
  seen[$p]=1
  if ! dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed'; then
    missing+=("$p")
  fi
done

if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#seen[@]} packages already installed"
else
  if [ "$(id -u)" -ne 0 ] && [ "${#SUDO[@]}" -eq 0 ]; then
    echo "setup: missing packages: ${missing[*]}" >&2
    echo "setup: not root and no sudo: install them as root, then run this again" >&2
    exit 1
  fi
  echo "setup: installing ${#missing[@]} missing package(s): ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${SUDO[@]}" apt-get update
  "${SUDO[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
  echo "setup: packages installed"
fi

if [ "${MCV_SKIP_DATA:-0}" != "1" ]; then
  if ! bash "$here/fetch-data.sh"; then
    # Offline machines still build and run the synthetic tests; real-data tests skip
    # with a message naming the missing file. MCV_REQUIRE_DATA=1 makes this an error.
    if [ "${MCV_REQUIRE_DATA:-0}" = "1" ]; then
      echo "setup: ERROR: real volumes could not be fetched" >&2
      exit 1
    fi
    echo "setup: WARNING: real volumes could not all be fetched (see above); tests that" >&2
    echo "setup:          need them will be skipped. Re-run scripts/fetch-data.sh online." >&2
  fi
fi
echo "setup: done"
