# pvbatch_runs.sh: sourced by the tests that run a check script several times, a first run
# that writes the reference (or the recording) and later runs, often under mpiexec, that
# compare with it (test_mpi.sh, test_mpi_no_opengl.sh, test_mpi_probe_brush.sh,
# mpi_reference_compare.sh, record_replay.sh). Sets $here, the folder of the test and of
# its check scripts.
#   fresh_dir NAME             prints MCV_OUTPUT_DIR/NAME (default /tmp/NAME), emptied and
#                              created
#   first_run PROGRAM SCRIPT [ARGS...]
#                              PROGRAM (pvbatch or pvpython) SCRIPT ARGS under a virtual X
#                              server; when it fails the test ends with its status (125 when
#                              the data is missing: CTest's skip)
#   first_run_into PROGRAM CHECK OPTION
#                              sets $out to fresh_dir <CHECK without .py> and runs
#                              first_run PROGRAM CHECK OPTION $out (--reference, --record)
#   mpi_environment            lets Open MPI run as root and more processes than cores, one
#                              OpenMP thread per process (keeps several processes sane on a
#                              small machine); other MPIs ignore the OMPI_ variables
#   mpi_run N SECONDS SCRIPT [ARGS...]
#                              mpiexec -np N pvbatch --mpi SCRIPT ARGS under a virtual X
#                              server, stopped after SECONDS (status 124 or 137 then)
#   mpi_run_twice_if_hung N SECONDS SCRIPT [ARGS...]
#                              mpi_run, once more when the first run hung; the last run's
#                              status
# mpi_run needs $pvbatch and $mpiexec.

here="$(cd "$(dirname "$0")" && pwd)"

fresh_dir() {
  _dir="${MCV_OUTPUT_DIR:-/tmp}/$1"
  rm -rf "$_dir" && mkdir -p "$_dir" && echo "$_dir"
}

first_run() {
  _program="$1"
  _script="$2"
  shift 2
  sh "$here/run_pvbatch.sh" "$_program" "$here/$_script" "$@" || exit $?
}

first_run_into() {
  out=$(fresh_dir "$(basename "$2" .py)")
  first_run "$1" "$2" "$3" "$out"
}

mpi_environment() {
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  export OMPI_MCA_rmaps_base_oversubscribe=1 OMP_NUM_THREADS=1
}

mpi_run() {
  _n="$1"
  _seconds="$2"
  _script="$3"
  shift 3
  timeout -k 10 "$_seconds" sh "$here/run_pvbatch.sh" "$mpiexec" -np "$_n" "$pvbatch" --mpi \
    "$here/$_script" "$@"
}

# pvbatch --mpi can hang in its first volume render: process 0 waits in ParaView's own
# render (vtkPVRenderView::Render -> RedistributeDataForOrderedCompositing -> AllGather)
# while another waits for the next RMI (vtkMultiProcessController::ProcessRMIs), both
# spinning in MPI; ParaView's condition when a process cannot render with OpenGL
# (test_mpi_no_opengl.sh, docs/client-server.md). A run that finishes is well within its
# SECONDS; a hung one is stopped (timeout signals its process group; what is left of the
# script's processes is killed) and run once more. A wrong answer still fails at once.
mpi_run_twice_if_hung() {
  for _attempt in 1 2; do
    echo "== mpiexec -np $1 pvbatch --mpi $3 (attempt $_attempt)"
    mpi_run "$@"
    _rc=$?
    [ $_rc -eq 124 ] || [ $_rc -eq 137 ] || return $_rc
    pkill -KILL -f "$here/$3" 2>/dev/null
    echo "pvbatch_runs.sh: mpiexec -np $1 pvbatch --mpi $3 hung (no answer in $2 s)" >&2
  done
  return $_rc
}
