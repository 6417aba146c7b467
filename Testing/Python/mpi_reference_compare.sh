#!/bin/sh
# mpi_reference_compare.sh PVBATCH MPIEXEC CHECK [PROCESSES...]: a check script's answers on
# each count of PROCESSES (default 2) against one process's: `pvbatch CHECK --reference DIR`
# writes the inputs and the one-process answers into DIR (MCV_OUTPUT_DIR/<CHECK without
# .py>), then for each count N `mpiexec -np N pvbatch --mpi CHECK --compare DIR` compares
# its own with them (N = 1: a plain `pvbatch CHECK --compare DIR`, as a user runs it
# without MPI). Exit 125 (skipped) when the data is missing.
set -u
pvbatch="$1"
mpiexec="$2"
check="$3"
shift 3
. "$(dirname "$0")/pvbatch_runs.sh"
first_run_into "$pvbatch" "$check" --reference
mpi_environment
for n in ${*:-2}; do
  echo "== $n process(es)"
  if [ "$n" -eq 1 ]; then
    timeout -k 10 300 sh "$here/run_pvbatch.sh" "$pvbatch" "$here/$check" --compare "$out"
  else
    mpi_run "$n" 300 "$check" --compare "$out"
  fi || exit 1
done
