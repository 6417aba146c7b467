#!/bin/sh
# test_mpi_legend.sh PVBATCH MPIEXEC PVPYTHON PVSERVER: the Gaussian widget legend shows
# the whole volume's shares in one process, split over 2 and 3 MPI processes
# (mpi_legend_check.py, a synthetic volume with known shares), with processes that hold no
# voxel (--thin on 3), and in pvpython connected to a pvserver of 2 processes (started
# under its own virtual X server on a free port, stopped after the run).
set -u
pvbatch="$1"
mpiexec="$2"
pvpython="$3"
pvserver="$4"
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

. "$here/pvserver_control.sh"
unset PV_PLUGIN_PATH  # the client loads the plugin on both sides
legend_client() {
  echo "== pvpython, a pvserver of 2 processes"
  sh "$here/run_pvbatch.sh" "$pvpython" "$here/mpi_legend_check.py" --out "$out" \
    --connect "$port"
}
run_on_server 2 legend_client
