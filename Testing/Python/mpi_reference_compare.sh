#!/bin/sh
# mpi_reference_compare.sh PVBATCH MPIEXEC CHECK: a check script's answers on 2 MPI processes
# against one process's: `pvbatch CHECK --reference DIR` writes the inputs and the
# one-process answers into DIR (MCV_OUTPUT_DIR/<CHECK without .py>), then
# `mpiexec -np 2 pvbatch --mpi CHECK --compare DIR` compares its own with them. Exit 125
# (skipped) when the data is missing.
set -u
pvbatch="$1"
mpiexec="$2"
check="$3"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/$(basename "$check" .py)"
rm -rf "$out"
sh "$here/run_pvbatch.sh" "$pvbatch" "$here/$check" --reference "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc
# Open MPI refuses root and more processes than cores unless told (ignored by other MPIs).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
echo "== 2 processes"
OMP_NUM_THREADS=1 timeout -k 10 300 sh "$here/run_pvbatch.sh" "$mpiexec" -np 2 "$pvbatch" --mpi \
  "$here/$check" --compare "$out"
