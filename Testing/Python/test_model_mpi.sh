#!/bin/sh
# test_model_mpi.sh PVBATCH MPIEXEC: reduction models on 2 MPI processes equal one process
# (mpi_model_check.py): one reference run in one process (volumes, models, coordinates),
# then 2 processes compared with it. Exit 125
# (skipped) when the data is missing.
set -u
pvbatch="$1"
mpiexec="$2"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/mpi_model"
rm -rf "$out"
sh "$here/run_pvbatch.sh" "$pvbatch" "$here/mpi_model_check.py" --reference "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
echo "== 2 processes"
OMP_NUM_THREADS=1 timeout -k 10 300 sh "$here/run_pvbatch.sh" "$mpiexec" -np 2 "$pvbatch" --mpi \
  "$here/mpi_model_check.py" --compare "$out"
