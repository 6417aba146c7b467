#!/bin/sh
# test_mpi_probe_brush.sh PVPYTHON PVBATCH MPIEXEC [PROCESSES...]: the exploration loop
# (client_server_loop_check.py) under mpiexec pvbatch --mpi with each count in PROCESSES
# (default 2), every answer compared with a built-in pvpython run's. Exit 125 (skipped)
# when the data is missing.
set -u
pvpython="$1"
pvbatch="$2"
mpiexec="$3"
shift 3
counts="${*:-2}"
here="$(cd "$(dirname "$0")" && pwd)"
out="${MCV_OUTPUT_DIR:-/tmp}/mpi_probe_brush"
rm -rf "$out"
mkdir -p "$out"
sh "$here/run_pvbatch.sh" "$pvpython" "$here/client_server_loop_check.py" --reference "$out"
rc=$?
[ $rc -eq 0 ] || exit $rc
# Open MPI refuses root and more processes than cores unless told (ignored by other MPIs).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
for n in $counts; do
  echo "== mpiexec -np $n pvbatch --mpi"
  OMP_NUM_THREADS=1 sh "$here/run_pvbatch.sh" "$mpiexec" -np "$n" "$pvbatch" --mpi \
    "$here/client_server_loop_check.py" --compare "$out" --processes "$n" || exit 1
done
exit 0
