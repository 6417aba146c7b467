#!/usr/bin/env bash
# The main job from a fresh Debian 12 machine: installs what is missing, fetches the real
# volumes, builds, then runs the whole method on the real 3-channel brain (Colin27 T1 +
# AAL + Brodmann from mricron-data) under pvbatch: 24D features -> Isomap -> seeded
# Gaussian widgets -> Gaussian TF volume rendering -> best viewpoint. Writes best/worst
# views, the reduced domain beside the volume, the eigenvalue spectrum, PCA / Isomap / LLE
# side by side (methods.png) and report.json
# into ./output/transfer_function. Arguments go to Examples/transfer_function.py
# (--help lists them, e.g. --features 6D --output DIR; --upsample 2 resamples the channels
# to 57 M voxels first; --chain features runs MultichannelFeatures -> DimensionReduction, keeping the Features array).
# report.json records the time and the peak resident memory of each stage.
# Exit code 0 when the run is complete; 1 with one "error: ..." line (a filter's error, too
# little memory, a disk full or read-only); 130 / 143 on SIGINT / SIGTERM. Only a complete
# run replaces ./output/transfer_function (docs/reliability.md).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$repo/scripts/setup.sh"
bash "$repo/scripts/build.sh"
# The job itself (plugin, display, a trial start under memory limits): scripts/main-job.sh.
exec bash "$repo/scripts/main-job.sh" --output "$repo/output/transfer_function" "$@"
