#!/bin/sh
# test_mpi.sh PVBATCH MPIEXEC: the suite's filters under ParaView's parallel engine give the
# one-process answer on the real 3-channel brain (mpi_parallel_check.py): one reference run
# in one process, then 2 and 3 MPI processes compared with it. Exit 125 (skipped) when the
# data is missing.
set -u
pvbatch="$1"
mpiexec="$2"
. "$(dirname "$0")/pvbatch_runs.sh"
out=$(fresh_dir mpi_reference)
first_run "$pvbatch" mpi_parallel_check.py --reference "$out"
mpi_environment
for ranks in 2 3; do
  echo "== $ranks processes"
  mpi_run $ranks 600 mpi_parallel_check.py --compare "$out" || exit 1
done
# More processes than the volume splits in (2 x 2 x 2 voxels on 2 and 4 processes): a
# process that owns no voxel takes part with nothing, and the result is one process's.
thin=$(fresh_dir mpi_thin_reference)
first_run "$pvbatch" mpi_parallel_check.py --thin --reference "$thin"
for ranks in 2 4; do
  echo "== $ranks processes, 2 x 2 x 2 voxels"
  mpi_run $ranks 300 mpi_parallel_check.py --thin --compare "$thin" || exit 1
done
# Counts over the whole volume (NaN/Inf voxels), one process and split: a synthetic volume.
first_run "$pvbatch" mpi_nonfinite_check.py
echo "== 3 processes, NaN/Inf voxels"
mpi_run 3 300 mpi_nonfinite_check.py || exit 1
# The Gaussian TF Volume (per sample and per voxel): 2 processes draw the one-process picture.
# A run that finishes takes well under a minute; a hung one is stopped after 240 s and run
# once more (mpi_run_twice_if_hung); a wrong picture still fails.
gtf=$(fresh_dir mpi_gaussian_tf)
first_run "$pvbatch" mpi_gaussian_tf_check.py --reference "$gtf"
echo "== 2 processes, Gaussian TF Volume"
mpi_run_twice_if_hung 2 240 mpi_gaussian_tf_check.py --compare "$gtf" || exit 1
