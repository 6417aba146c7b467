#!/bin/sh
# test_omezarr_mpi.sh PVBATCH MPIEXEC: the OME-Zarr reader under ParaView's parallel engine
# (mpi_omezarr_check.py): the real 3-channel brain written once as OME-Zarr (32^3 chunks),
# then read by 1 and 2 MPI processes: each process's piece equals the source, and each
# read only the chunks of its piece (bytes read per process printed). Exit 125 (skipped)
# when the data is missing.
set -u
pvbatch="$1"
mpiexec="$2"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/mpi_omezarr"
rm -rf "$out"
sh "$here/run_pvbatch.sh" "$pvbatch" "$here/mpi_omezarr_check.py" --write "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc
echo "== 1 process"
sh "$here/run_pvbatch.sh" "$pvbatch" "$here/mpi_omezarr_check.py" --compare "$out" || exit 1
# Open MPI refuses root and more processes than cores unless told (ignored by other MPIs).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
echo "== 2 processes"
OMP_NUM_THREADS=1 sh "$here/run_pvbatch.sh" "$mpiexec" -np 2 "$pvbatch" --mpi \
  "$here/mpi_omezarr_check.py" --compare "$out" || exit 1
