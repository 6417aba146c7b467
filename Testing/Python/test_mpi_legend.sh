#!/bin/sh
# test_mpi_legend.sh PVBATCH MPIEXEC: the Gaussian widget legend shows the whole volume's
# shares in one process and split over 2 and 3 MPI processes (mpi_legend_check.py, a
# synthetic volume with known shares), and with processes that hold no voxel (--thin on 3).
set -u
pvbatch="$1"
mpiexec="$2"
. "$(dirname "$0")/pvbatch_runs.sh"
out=$(fresh_dir mpi_legend)
echo "== 1 process"
first_run "$pvbatch" mpi_legend_check.py --out "$out"
first_run "$pvbatch" mpi_legend_check.py --thin --out "$out"
mpi_environment
for ranks in 2 3; do
  echo "== $ranks processes"
  mpi_run_twice_if_hung $ranks 240 mpi_legend_check.py --out "$out" || exit 1
done
echo "== 3 processes, 2 x 2 x 2 voxels"
mpi_run_twice_if_hung 3 240 mpi_legend_check.py --thin --out "$out" || exit 1
