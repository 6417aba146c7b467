#!/bin/sh
# test_mpi_no_opengl.sh PVBATCH MPIEXEC: mpiexec pvbatch --mpi with 2 processes of which
# the second cannot render (Mesa offers it OpenGL 2.1; ParaView needs 3.2), as happens when
# a process gets no usable display. ParaView then renders on process 0 only, yet the first
# volume render redistributes the data for ordered compositing, which needs every process:
# ParaView 5.11 waits forever. (1) ParaView's own Volume representation does hang (no
# "rendered" within 90 s, ParaView's "remote rendering which, however, is not available"
# printed); (2) the plugin's show_gaussian_tf stops at once with an error naming the cause
# (mpi_no_opengl_check.py).
set -u
pvbatch="$1"
mpiexec="$2"
. "$(dirname "$0")/pvbatch_runs.sh"
out=$(fresh_dir mpi_no_opengl)
mpi_environment
export PYTHONPATH="$here${PYTHONPATH:+:$PYTHONPATH}"
run() {  # run MODE SECONDS: the two-process run under one virtual X server
  timeout -k 10 "$2" sh "$here/run_pvbatch.sh" "$mpiexec" \
    -np 1 "$pvbatch" --mpi "$here/mpi_no_opengl_check.py" "$1" : \
    -np 1 env MESA_GL_VERSION_OVERRIDE=2.1 "$pvbatch" --mpi "$here/mpi_no_opengl_check.py" "$1"
}
echo "== ParaView's Volume representation (expected to hang; stopped after 90 s)"
# Straight under xvfb-run (run_pvbatch.sh prints a run's output only when it ends, and
# this one is stopped): the output is read while it hangs. A run whose X server failed
# at start-up ("bad X server connection") is tried again, up to 3 times.
for attempt in 1 2 3; do
  timeout -k 10 90 xvfb-run -a -s "-screen 0 640x480x24 -noreset" "$mpiexec" \
    -np 1 "$pvbatch" --mpi "$here/mpi_no_opengl_check.py" --paraview : \
    -np 1 env MESA_GL_VERSION_OVERRIDE=2.1 "$pvbatch" --mpi "$here/mpi_no_opengl_check.py" \
    --paraview >"$out/paraview.log" 2>&1
  rc=$?
  grep -q "bad X server connection" "$out/paraview.log" || break
  echo "test_mpi_no_opengl.sh: X server start-up failed (attempt $attempt), retrying"
done
cat "$out/paraview.log"
failed=0
if grep -q "remote rendering available: False" "$out/paraview.log" &&
   grep -q "which, however, is not available" "$out/paraview.log" &&
   ! grep -q "^rendered" "$out/paraview.log" && [ $rc -eq 124 -o $rc -eq 137 ]; then
  echo "ok   ParaView's own first volume render hangs when a process cannot render (exit $rc)"
else
  echo "FAIL ParaView's own volume render: expected the condition and a hang (exit $rc)"
  failed=1
fi
echo "== the plugin's show_gaussian_tf"
run --helper 300
rc=$?
[ $rc -eq 0 ] || { echo "FAIL show_gaussian_tf under the same condition (exit $rc)"; failed=1; }
exit $failed
