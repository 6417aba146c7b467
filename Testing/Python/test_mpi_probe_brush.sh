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
. "$(dirname "$0")/pvbatch_runs.sh"
out=$(fresh_dir mpi_probe_brush)
first_run "$pvpython" client_server_loop_check.py --reference "$out"
mpi_environment
# pvbatch --mpi can hang in its first volume render (pvbatch_runs.sh says when): each run
# is given 360 s, and one that hangs is tried once more. Any other failure fails at once.
for n in $counts; do
  mpi_run_twice_if_hung "$n" 360 client_server_loop_check.py --compare "$out" --processes "$n" ||
    exit 1
done
