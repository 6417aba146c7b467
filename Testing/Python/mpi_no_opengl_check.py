"""A pvbatch --mpi run in which one process cannot render (run by test_mpi_no_opengl.sh
under `mpiexec -np 1 pvbatch --mpi THIS : -np 1 env MESA_GL_VERSION_OVERRIDE=2.1 pvbatch
--mpi THIS`: Mesa then offers the second process OpenGL 2.1, below the 3.2 ParaView
needs, so ParaView finds remote rendering not available).

  --helper     the plugin's show_gaussian_tf on a volume of reduced coordinates (a Wavelet's
               point coordinates): must stop with the RuntimeError that names the cause,
               at once, instead of showing the volume (exit 0 when it did)
  --paraview   ParaView's own Volume representation and Render: the hang the helper
               avoids (the caller expects no "rendered" line before its timeout)"""
import os
import sys

from paraview import simple

import mcv_testing as T

pm = simple.servermanager.vtkProcessModule.GetProcessModule()
view = simple.CreateView("RenderView")
view.ViewSize = [200, 200]
available = view.GetClientSideObject().GetRemoteRenderingAvailable()
print("processes %d, remote rendering available: %s" % (pm.GetNumberOfLocalPartitions(),
                                                         bool(available)))
sys.stdout.flush()
wavelet = simple.Wavelet(WholeExtent=[-10, 10, -10, 10, -10, 10])
coords = simple.Calculator(Input=wavelet, Function="coords",
                           ResultArrayName="ReducedCoordinates", ResultArrayType="Float")
if "--paraview" in sys.argv:
    display = simple.Show(wavelet, view)
    display.Representation = "Volume"
    simple.ColorBy(display, ("POINTS", "RTData"))
    simple.Render(view)
    print("rendered")
    sys.stdout.flush()
    os._exit(0)

C = T.Checker("mpi_no_opengl_check")
mce = T.load_plugin(globals())
C.check(pm.GetNumberOfLocalPartitions() == 2 and not available,
        "2 processes, the second without OpenGL 3.2: remote rendering not available")
try:
    mce.show_gaussian_tf(coords, view, widgets=[0, 0, 0, 5, 1, 0, 0, 1])
    simple.Render(view)
    message = None
except RuntimeError as error:
    message = str(error)
C.check(message is not None and "cannot render" in message and "OpenGL" in message and
        "xvfb-run" in message,
        "show_gaussian_tf stops with an error that names the cause: %s" % message)
C.finish_parallel()
