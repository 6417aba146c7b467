"""Shared helpers of the pvbatch tests of the MultichannelExplorer plugin.

Every test is run as ``xvfb-run -a pvbatch <test>.py`` (see CMakeLists.txt) with:
  MCV_PLUGIN      the plugin library (else: found through PV_PLUGIN_PATH, else
                  <repo>/build-pv/lib/paraview-5.11/plugins/MultichannelExplorer/...)
  MCV_DATA_DIR    the real volumes (default <repo>/.cache/volumes)
  MCV_OUTPUT_DIR  where screenshots go (default <repo>/build-pv/Testing/Python/output)
A test exits 0 on success, 1 on failure, 125 when its data is missing (CTest: skipped).
No numpy: ParaView's Python on Debian 12 has none.
"""

import math
import os
import shutil
import sys

SKIP = 125
REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def data_dir():
    return os.environ.get("MCV_DATA_DIR") or os.path.join(REPO, ".cache", "volumes")


def output_dir():
    out = os.environ.get("MCV_OUTPUT_DIR") or os.path.join(
        REPO, "build-pv", "Testing", "Python", "output")
    os.makedirs(out, exist_ok=True)
    return out


def fresh_output_dir(name):
    """The test's own folder <output_dir>/name, emptied of an earlier run's files."""
    out = os.path.join(output_dir(), name)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    return out


def output_of(proxy, port=0):
    """The proxy's output data after an update (built-in session: the object itself)."""
    proxy.UpdatePipeline()
    return proxy.GetClientSideObject().GetOutputDataObject(port)


def programmable_image(dims, name, value="v", body="", components=1, array_type="vtkFloatArray",
                       scalars=False):
    """A ProgrammableSource of image data of `dims` with one point array `name` of
    `components` components: for voxel (i, j, k), the Python lines `body` run (they may set
    variables, e.g. v), then component c gets the expression `value` (of i, j, k, c and
    those variables). No numpy: ParaView's Python on Debian 12 has none. `scalars`: the
    array is the point data's active scalars."""
    from paraview.simple import ProgrammableSource
    src = ProgrammableSource()
    src.OutputDataSetType = "vtkImageData"
    src.ScriptRequestInformation = (
        "from paraview import util\n"
        "util.SetOutputWholeExtent(self, [0, %d, 0, %d, 0, %d])\n"
        % (dims[0] - 1, dims[1] - 1, dims[2] - 1))
    src.Script = (
        "import math\n"
        "from vtkmodules.vtkCommonCore import %s\n"
        "out = self.GetOutput()\n"
        "out.SetExtent(0, %d, 0, %d, 0, %d)\n"
        "a = %s()\n"
        "a.SetName('%s')\n"
        "a.SetNumberOfComponents(%d)\n"
        "a.SetNumberOfTuples(%d)\n"
        "n = 0\n"
        "for k in range(%d):\n"
        "    for j in range(%d):\n"
        "        for i in range(%d):\n"
        "%s\n"
        "            for c in range(%d):\n"
        "                a.SetComponent(n, c, %s)\n"
        "            n += 1\n"
        "out.GetPointData().%s(a)\n"
        % (array_type, dims[0] - 1, dims[1] - 1, dims[2] - 1, array_type, name, components,
           dims[0] * dims[1] * dims[2], dims[2], dims[1], dims[0],
           "\n".join("            " + line for line in body.splitlines()) or "            pass",
           components, value, "SetScalars" if scalars else "AddArray"))
    return src


def image_without_arrays(last=9):
    """A ProgrammableSource of image data of extent [0, last] on each axis and no array
    (last = -1: an empty extent): the bad inputs of the filters' argument checks."""
    from paraview.simple import ProgrammableSource

    src = ProgrammableSource()
    src.OutputDataSetType = "vtkImageData"
    src.ScriptRequestInformation = (
        "from paraview import util\n"
        "util.SetOutputWholeExtent(self, [0, %d, 0, %d, 0, %d])\n" % (last, last, last))
    src.Script = "self.GetOutput().SetExtent(0, %d, 0, %d, 0, %d)\n" % (last, last, last)
    return src


def data_file(name):
    """Path of a real volume; exits with SKIP when it is missing."""
    path = os.path.join(data_dir(), name)
    if not os.path.exists(path):
        print("SKIP: %s not found (run scripts/fetch-data.sh)" % path)
        sys.exit(SKIP)
    return path


BRAIN = ("ch2", "aal", "brodmann")  # the real 3-channel brain: Colin27 T1, AAL, Brodmann


def volume_arrays(image):
    """{array name: values as a (z, y, x) numpy array} of a vtkImageData's point arrays."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    nx, ny, nz = image.GetDimensions()
    pd = image.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)).reshape(nz, ny, nx)
            for i in range(pd.GetNumberOfArrays())}


def field_strings(image, name):
    """The values of the field data array `name` as a list; None when there is none."""
    a = image.GetFieldData().GetAbstractArray(name)
    return None if a is None else [a.GetValue(i) for i in range(a.GetNumberOfValues())]


def brain_series(folder, factors=(1.0, 1.0, 1.2), step=3):
    """A time series of the real brain (Colin27 T1 + AAL, every `step`-th voxel) as
    folder/step_<i>.vti, step i's T1 multiplied by factors[i]. Returns (paths, t1, aal)."""
    import numpy as np

    brain = brain_arrays(("ch2", "aal"), step=step).astype(np.float32)
    t1, aal = brain[0], brain[1]
    paths = [write_vti(os.path.join(folder, "step_%d.vti" % i), [("ch2", t1 * f), ("aal", aal)])
             for i, f in enumerate(factors)]
    return paths, t1, aal


def opened_brain_series(checker, folder, factors=(1.0, 1.0, 1.2)):
    """brain_series(folder, factors) opened as one ParaView time series, checked to have a
    time step per factor. Returns (series, its time values, paths, t1, aal)."""
    from paraview.simple import OpenDataFile

    paths, t1, aal = brain_series(folder, factors)
    series = OpenDataFile(paths)
    series.UpdatePipelineInformation()
    times = list(series.TimestepValues)
    checker.check(len(times) == len(factors),
                  "the series has %d time steps: %s" % (len(factors), times))
    return series, times, paths, t1, aal


def coordinates_at(reduction, time):
    """The reduction's ReducedCoordinates at `time` as numpy (None when there are none) and
    its output's ReductionModelSource field strings (None without a model)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reduction.UpdatePipeline(time)
    data = reduction.GetClientSideObject().GetOutputDataObject(0)
    array = data.GetPointData().GetArray("ReducedCoordinates")
    source = field_strings(data, "ReductionModelSource")
    return (None if array is None else vtk_to_numpy(array).copy()), source


def default_brain_reduction(size):
    """The chain a new user builds with every default: the real brain's three files ->
    MergeChannels -> MultichannelFeatures -> DimensionReduction, updated; and a render view
    of `size` pixels. Returns (reduction, view)."""
    from paraview import simple

    readers = [simple.OpenDataFile(data_file(f))
               for f in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
    merged = simple.MergeChannels(Input=readers)
    reduction = simple.DimensionReduction(Input=simple.MultichannelFeatures(Input=merged))
    reduction.UpdatePipeline()
    view = simple.CreateRenderView()
    view.ViewSize = list(size)
    return reduction, view


def pca_reduction(mce, source, **props):
    """reduce_multichannel(source, "PCA", "6D") on a sample of 3000, with `props` set."""
    _, reduction = mce.reduce_multichannel(source, "PCA", "6D", ReferenceSampleSize=3000)
    for name, value in props.items():
        setattr(reduction, name, value)
    return reduction


def brain_arrays(names=BRAIN, step=1):
    """The real volumes `names` (ch2, aal, brodmann: 181 x 217 x 181, one grid) read with the
    plugin's NIfTI reader, every `step`-th voxel per axis, as one (c, z, y, x) numpy array
    of their own type. Exits with SKIP when a volume is missing."""
    import numpy as np
    from paraview import servermanager, simple

    channels = []
    for n in names:
        reader = simple.NIfTIImageReader(FileName=data_file(n + ".nii.gz"))
        values = list(volume_arrays(servermanager.Fetch(reader)).values())[0]
        channels.append(np.ascontiguousarray(values[::step, ::step, ::step]))
        simple.Delete(reader)
    return np.stack(channels)


def write_vti(path, channels, spacing=(3.0, 3.0, 3.0)):
    """Writes `channels`, a list of (name, (z, y, x) array), as float32 point arrays of one
    .vti file (ParaView's own format, read by OpenDataFile). Returns `path`."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    image = vtkImageData()
    nz, ny, nx = channels[0][1].shape
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(*spacing)
    for name, values in channels:
        array = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float32).ravel(), deep=1)
        array.SetName(name)
        image.GetPointData().AddArray(array)
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    if not writer.Write():
        raise RuntimeError("could not write %s" % path)
    return path


def load_plugin(ns):
    """Loads the plugin (unless PV_PLUGIN_PATH already did) and returns the module."""
    from paraview import simple

    if not hasattr(simple, "BestViewpoint"):
        plugin = os.environ.get("MCV_PLUGIN")
        if not plugin:
            for d in os.environ.get("PV_PLUGIN_PATH", "").split(os.pathsep) + [
                    os.path.join(REPO, "build-pv", "lib", "paraview-5.11", "plugins",
                                 "MultichannelExplorer")]:
                candidate = os.path.join(d, "MultichannelExplorer.so")
                if d and os.path.exists(candidate):
                    plugin = candidate
                    break
        if not plugin:
            print("FAIL: MultichannelExplorer plugin not found (set MCV_PLUGIN)")
            sys.exit(1)
        simple.LoadPlugin(plugin, remote=False)  # new constructors go into paraview.simple
    ns.update({k: getattr(simple, k) for k in ("BestViewpoint", "VolPackDenReader",
                                                "NIfTIImageReader")})
    import multichannel_explorer

    return multichannel_explorer


def brain_channels():
    """The real 3-channel brain (Colin27 T1 ch2 + the AAL and Brodmann atlases) on one grid:
    AppendAttributes of the three readers (not updated)."""
    from paraview.simple import AppendAttributes, OpenDataFile

    return AppendAttributes(Input=[OpenDataFile(data_file(n))
                                   for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")])


def local_processes():
    """The number of processes pvbatch runs in (mpiexec -np N pvbatch --mpi; 1 without)."""
    from paraview import servermanager

    return servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()


def parallel_checker(name):
    """(processes, a Checker named `name` and the number of processes it runs in)."""
    processes = local_processes()
    return processes, Checker("%s (%d process%s)" % (name, processes,
                                                   "es" if processes > 1 else ""))


def reference_compare_parser():
    """The argument parser of a check script run once with --reference DIR (one process
    writes the inputs and its answers into DIR) and then with --compare DIR (its answers,
    often on several MPI processes, compared with those): mpi_reference_compare.sh's
    calling convention. Returns (parser, the group of those modes, for the script's own)."""
    import argparse

    parser = argparse.ArgumentParser()
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--reference", metavar="DIR")
    mode.add_argument("--compare", metavar="DIR")
    return parser, mode


def brain_subset(step):
    """The real 3-channel brain (brain_channels, updated), every `step`-th voxel per axis
    through ExtractSubset, which under MPI each process reads its own piece of. The
    properties are given to the constructors, so a trace records them."""
    from paraview import simple

    merged = brain_channels()
    merged.UpdatePipeline()
    return simple.ExtractSubset(Input=merged, VOI=merged.GetDataInformation().GetExtent(),
                                SampleRateI=step, SampleRateJ=step, SampleRateK=step)


def open_series(files, checker):
    """`files` opened as one time series (a step per file), the animation on its steps:
    (reader, its time values, the animation scene); `checker` checks there is a step per
    file."""
    from paraview import simple

    series = simple.OpenDataFile(files)
    series.UpdatePipelineInformation()
    times = [float(t) for t in series.TimestepValues]
    checker.check(len(times) == len(files), "the %d files are one series of %d time steps %s"
                  % (len(files), len(files), times))
    scene = simple.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    return series, times, scene


def render_view(size, background=(0.0, 0.0, 0.0), axes=False):
    """A new render view of `size` pixels with its own `background` colour (not the colour
    palette's) and the orientation axes shown or not."""
    from paraview import simple

    view = simple.CreateView("RenderView")
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = int(axes)
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:  # ParaView before 5.10: the background is the view's own
        pass
    view.Background = list(background)
    return view


def run_pvbatch(program, args, **kwargs):
    """subprocess.run of PROGRAM (pvbatch) ARGS under its own virtual X server
    (run_pvbatch.sh, which retries an X server that failed to start), its output and
    errors as one text in .stdout; `kwargs` go to subprocess.run (cwd, env, timeout)."""
    import subprocess

    here = os.path.dirname(os.path.abspath(__file__))
    return subprocess.run(["sh", os.path.join(here, "run_pvbatch.sh"), program] + list(args),
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, **kwargs)


def run_example(checker, script, args, output, tail=1500):
    """pvbatch Examples/SCRIPT ARGS (with --plugin $MCV_PLUGIN when it is set), checked to
    exit 0 and to write OUTPUT/report.json; prints the last `tail` characters of its output.
    Returns the report; without one the test ends there (checker.finish)."""
    import json

    command = [os.path.join(REPO, "Examples", script)] + list(args)
    if os.environ.get("MCV_PLUGIN"):
        command += ["--plugin", os.environ["MCV_PLUGIN"]]
    run = run_pvbatch("pvbatch", command)
    print(run.stdout[-tail:])
    checker.check(run.returncode == 0, "%s %s ran (exit %d)"
                  % (script, " ".join(str(a) for a in args), run.returncode))
    path = os.path.join(output, "report.json")
    if not checker.check(os.path.exists(path), "%s written" % path):
        checker.finish()
    with open(path) as f:
        return json.load(f)


class Checker(object):
    """Collects failed checks; finish() prints a summary and exits."""

    def __init__(self, name):
        self.name = name
        self.failures = []
        self.count = 0

    def check(self, condition, message):
        self.count += 1
        status = "ok  " if condition else "FAIL"
        print("%s %s" % (status, message))
        sys.stdout.flush()
        if not condition:
            self.failures.append(message)
        return condition

    def summary(self):
        print("%s: %d checks, %d failed" % (self.name, self.count, len(self.failures)))
        for f in self.failures:
            print("  failed: " + f)
        sys.stdout.flush()

    def finish(self):
        self.summary()
        # os._exit: pvbatch's own exit path must not turn a failure into 0 (or crash).
        os._exit(1 if self.failures else 0)

    def finish_parallel(self):
        """finish() for pvbatch --mpi: on success it returns, so that pvbatch shuts the
        other processes down itself (exiting here would make mpiexec abort them)."""
        self.summary()
        if self.failures:
            os._exit(1)


class Messages(object):
    """Error and warning messages of one VTK object (the server-side object of a proxy in
    pvbatch's built-in session), caught through vtkCommand observers."""

    def __init__(self, proxy_or_object):
        from vtkmodules.util.misc import calldata_type
        from vtkmodules.util.vtkConstants import VTK_STRING

        obj = proxy_or_object
        if hasattr(obj, "GetClientSideObject"):
            obj = obj.GetClientSideObject()
        self.object = obj
        self.errors = []
        self.warnings = []

        @calldata_type(VTK_STRING)
        def on_error(caller, event, text):
            self.errors.append(str(text))

        @calldata_type(VTK_STRING)
        def on_warning(caller, event, text):
            self.warnings.append(str(text))

        self._callbacks = (on_error, on_warning)  # keep them alive
        watched = [obj]
        if hasattr(obj, "GetReader") and obj.GetReader() is not None:
            # A file-series reader (the plugin's NIfTI and MetaImage readers): the reader
            # of each file inside it reports the file's problems.
            watched.append(obj.GetReader())
        for o in watched:
            o.AddObserver("ErrorEvent", on_error)
            o.AddObserver("WarningEvent", on_warning)

    def clear(self):
        del self.errors[:]
        del self.warnings[:]

    def any_error(self, *words):
        return any(all(w.lower() in e.lower() for w in words) for e in self.errors)

    def any_warning(self, *words):
        return any(all(w.lower() in e.lower() for w in words) for e in self.warnings)


def write_tiff_stack(image, folder, pattern="slice_%03d.tif"):
    """Writes each z slice of a vtkImageData as a 2D TIFF file in `folder` (vtkTIFFWriter
    writes a 3D input as one multi-page file instead); returns the paths in slice order."""
    from vtkmodules.vtkImagingCore import vtkExtractVOI
    from vtkmodules.vtkIOImage import vtkTIFFWriter

    os.makedirs(folder, exist_ok=True)
    ext = image.GetExtent()
    paths = []
    for k in range(ext[4], ext[5] + 1):
        voi = vtkExtractVOI()
        voi.SetInputData(image)
        voi.SetVOI(ext[0], ext[1], ext[2], ext[3], k, k)
        writer = vtkTIFFWriter()
        writer.SetInputConnection(voi.GetOutputPort())
        writer.SetFileName(os.path.join(folder, pattern % k))
        writer.Write()
        paths.append(writer.GetFileName())
    return paths


def close(a, b, tol, relative=True):
    """a equals b: dicts of the same keys, lists and tuples of the same length compared
    item by item, numbers where either is a float within `tol` (times max(1, |a|) when
    `relative`), anything else exactly."""
    if isinstance(a, dict):
        return isinstance(b, dict) and sorted(a) == sorted(b) and all(
            close(a[k], b[k], tol, relative) for k in a)
    if isinstance(a, (list, tuple)):
        return isinstance(b, (list, tuple)) and len(a) == len(b) and all(
            close(x, y, tol, relative) for x, y in zip(a, b))
    if isinstance(a, float) or isinstance(b, float):
        return a is not None and b is not None and \
            abs(a - b) <= tol * (max(1.0, abs(a)) if relative else 1.0)
    return a == b


PIXEL_TOLERANCE = 12  # a channel difference above this counts as a differing pixel


def _png_pixels(path):
    """(dimensions, components, pixel bytes) of a PNG file."""
    from vtkmodules.vtkIOImage import vtkPNGReader

    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    scalars = image.GetPointData().GetScalars()
    return image.GetDimensions(), scalars.GetNumberOfComponents(), bytes(memoryview(scalars))


def picture_difference(reference, picture):
    """(largest channel difference, fraction of the pixels differing by more than
    PIXEL_TOLERANCE, fraction of `picture`'s pixels not its background, the first pixel's
    colour) of two PNG files of the same size; None when their sizes differ."""
    (da, ca, a), (db, cb, b) = _png_pixels(reference), _png_pixels(picture)
    if da != db or ca != cb:
        return None
    worst, differing, lit = 0, 0, 0
    for p in range(0, len(a), ca):
        d = max(abs(a[p + c] - b[p + c]) for c in range(min(ca, 3)))
        worst = max(worst, d)
        differing += d > PIXEL_TOLERANCE
        lit += max(abs(b[p + c] - b[c]) for c in range(min(cb, 3))) > 20
    pixels = float(len(a) // ca)
    return worst, differing / pixels, lit / pixels


def blank_picture(path):
    """True when every pixel of the PNG file has the first pixel's colour (the background
    only: nothing was drawn)."""
    _, n, data = _png_pixels(path)
    return data == data[:n] * (len(data) // n)


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(v):
    n = norm(v)
    return [x / n for x in v] if n > 0 else [0.0 for _ in v]


def angle_deg(a, b, unsigned=False):
    c = dot(unit(a), unit(b))
    if unsigned:
        c = abs(c)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def all_finite(values):
    return all(math.isfinite(float(v)) for v in values)


def camera_direction(view):
    pos = [float(x) for x in view.CameraPosition]
    focal = [float(x) for x in view.CameraFocalPoint]
    return unit([f - p for f, p in zip(focal, pos)])


def volume_view(source, size=(480, 400), array=None):
    """A render view showing `source` as a volume coloured by `array` (default: first
    point array), transfer functions over the data range. Returns (view, display)."""
    from paraview import simple

    view = simple.CreateView("RenderView")
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 1
    display = simple.Show(source, view)
    display.SetRepresentationType("Volume")
    name = array or source.PointData.keys()[0]
    simple.ColorBy(display, ("POINTS", name))
    display.RescaleTransferFunctionToDataRange(True, False)
    simple.Render(view)
    return view, display


def image_ok(mce, path, checker, label, min_stddev=8.0, min_fraction=0.05):
    """Checks that a screenshot exists and is not blank (luminance spread and a part of
    the pixels different from the background)."""
    if not checker.check(os.path.exists(path) and os.path.getsize(path) > 0,
                         "%s: screenshot written (%s)" % (label, path)):
        return None
    stats = mce.image_statistics(path)
    checker.check(stats["stddev"] > min_stddev and
                  stats["non_background_fraction"] > min_fraction,
                  "%s: screenshot not blank (luminance stddev %.1f, %.0f%% non-background)"
                  % (label, stats["stddev"], 100 * stats["non_background_fraction"]))
    return stats


def support_directions():
    """The 128 directions of BestViewpoint's VisibleSupport, in its order: the six axes,
    then 122 on a Fibonacci lattice (vtkBestViewpoint.cxx, supportDirections)."""
    import math
    n = 122
    golden = math.pi * (3.0 - math.sqrt(5.0))
    directions = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    for i in range(n):
        z = 1.0 - (2.0 * i + 1.0) / n
        r = math.sqrt(1.0 - z * z)
        directions.append((r * math.cos(golden * i), r * math.sin(golden * i), z))
    return directions
