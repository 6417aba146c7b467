"""Snapshots of a collection of volumes, each from its best viewpoint, with an HTML index.

    xvfb-run -a pvbatch Examples/snapshot_collection.py --input DIR --output DIR
        [--force [NAME ...]] [--retry-failed] [--timeout S] [--size W H] [--plugin PATH]
        [--transfer-function FILE.mcvtf]

The "snapshot tool for volume databases" of the dissertation (section 7.6.1): for every
volume under --input (searched recursively) it renders a thumbnail from the best viewpoint
(camera along v3 of the 3D Harris interest points, +v3 or -v3 by image entropy) and writes
  OUTPUT/index.html         thumbnails, file name, dimensions, spacing, scalar type and
                            range, best direction, eigenvalue spectrum, time, or the error
  OUTPUT/index.json         the same records, machine-readable
  OUTPUT/thumbnails/*.png   one per volume
  OUTPUT/records/*.json     one per volume (what resuming looks at)

Volumes: NIfTI (.nii, .nii.gz), VolPack (.den), MetaImage (.mhd with its .raw, .mha),
TIFF (plain multi-page files, ImageJ hyperstacks), OME-TIFF (.ome.tif, .ome.tiff) and
OME-Zarr folders (.zarr, .ome.zarr) through the plugin's readers, which read a file whole or
refuse it with the reason (a truncated or corrupt file is an error entry that says why); VTK
image data (.vti) through ParaView's reader.
TIFF files of one folder whose names differ only in a trailing number (slice_000.tif,
slice_001.tif, ...) are one volume (a stack); any other .tif is a volume of its own.
Other files (.raw, .txt, ...) are ignored.

Channels: every channel of every file is listed by name in the index (with its type and
range). A file with several channels (a hyperstack, an OME file) is shown as a channel
composite, as a microscope's software shows it: each channel from black to its own colour
(the file's colours where it has them, OME-Zarr's omero colours; else ImageJ's composite
order red, green, blue, grey, cyan, magenta, yellow), over the same percentile ramp as a
single channel, the colours added and the opacity the largest of the channels' (at most a
quarter per voxel, so that what lies inside an outer channel shows through). Time
series: the first time step is shown and the record says how many there are.

Rendering: a linear opacity ramp and the Grayscale colour map from the 1st to the 99.5th
percentile of the non-empty voxels (those above the volume's minimum), as a user would set
them by hand, so that a long bright tail does not leave the anatomy black (the record
keeps the ramp); the best viewpoint follows that opacity. A volume with
several components per voxel (a 4D NIfTI such as a diffusion series) is shown and
analysed through its FIRST component (for diffusion MRI the b=0 image); the record says
how many components the file had.

Transfer function (--transfer-function FILE.mcvtf, saved with the Gaussian widgets
editor's Save... or multichannel_explorer.save_transfer_function): every volume is
reduced with the file's reduction model (no fit of its own: the channels matched by name)
and shown as a Gaussian TF Volume with the file's widgets (apply_transfer_function), so a
colour means the same tissue in every thumbnail. A volume without a channel of the model
gets an error entry naming the channel. Each record and caption gives the volume's share
of voxels outside the model (DimensionReduction's NumberOfOutOfModelVoxels over its
voxels): what the widgets were never placed for. The file is checked before any volume;
snapshots of another transfer function (or none), or of another --size, are not reused
on resume.

Isolation: each volume is rendered by a separate pvbatch process (a fresh session: no
proxy, view or transfer function leaks from one file into the next), under a time limit
(--timeout). A file that cannot be read, that crashes its reader or that runs out of time
gets an error entry; the run goes on.

Resume: a volume whose record and thumbnail exist (and whose file has not changed since)
is skipped, so an interrupted run can simply be started again. A volume that failed
before is skipped too when its file has not changed (--retry-failed tries again).
--force redoes every volume, --force NAME ... only the named ones (names as in the index).

Writing: a volume's new thumbnail and record are written beside the old ones and replace
them only once the thumbnail decodes at its size, so --force renders the new snapshot before
the old one goes, and a run killed at any moment leaves each volume either as it was or
done. The index lists every volume of the folder with its state (done, failed with the
reason, not yet tried) and how the run went: "7 of 8 done, 1 not yet tried, run interrupted
(SIGINT)", "run stopped: disk full (...)", "run in progress (pid N)" while it runs (and
after a SIGKILL). A failure that is not the file's fault (disk full, read-only or unwritable
output folder) keeps the previous snapshot, stops the run and is tried again by the next run
without --retry-failed. One run at a time per output folder: a second one stops at once,
naming the first one's pid (a flock on OUTPUT/.lock).

Exit code: 0 when at least one volume has a snapshot, else 1; 1 when the run had to stop
(disk full, read-only folder), 130 / 143 on SIGINT / SIGTERM. The last line printed is
"N of M volumes succeeded".
"""
import argparse
import html
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from example_support import load_plugin, render_view  # noqa: E402
import batch_output as B  # noqa: E402

THIS = os.path.abspath(__file__)
RECORD_VERSION = 2  # 2: channels listed by name (channel_list), composites
BAR_WIDTH = 20
# Extension -> format label. .raw/.img are data halves of a header file: not volumes.
FORMATS = [(".nii.gz", "NIfTI"), (".nii", "NIfTI"), (".den", "VolPack"), (".vti", "VTK image"),
           (".mhd", "MetaImage"), (".mha", "MetaImage"), (".ome.tiff", "OME-TIFF"),
           (".ome.tif", "OME-TIFF"), (".tiff", "TIFF"), (".tif", "TIFF")]
# Folders that are one volume each (never searched inside).
FOLDER_FORMATS = [(".ome.zarr", "OME-Zarr"), (".zarr", "OME-Zarr")]
# ImageJ's composite colours, in its channel order (C1 red, C2 green, ...).
CHANNEL_COLORS = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (0.75, 0.75, 0.75), (0, 1, 1), (1, 0, 1),
                  (1, 1, 0)]
# ParaView's and VTK's bookkeeping arrays, never channels.
INTERNAL_ARRAYS = ("vtkGhostType", "vtkValidPointMask")


def _format_of(name):
    low = name.lower()
    for ext, label in FORMATS:
        if low.endswith(ext):
            return ext, label
    return None, None


def _volume_id(name):
    """A file-system-safe, unique-enough id for thumbnails/records of a volume name."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name.replace(os.sep, "__")).strip("_") or "volume"


def discover(input_dir, output_dir):
    """The volumes under input_dir: [{"name", "id", "format", "files"}], sorted by name,
    and the number of files ignored. TIFF files named PREFIX<number>.tif in one folder
    form one stack (name: "PREFIX*.tif")."""
    volumes, ignored = [], 0
    out_real = os.path.realpath(output_dir)
    for root, dirs, files in os.walk(input_dir):
        # Never index our own output when it lies inside the input folder.
        dirs[:] = sorted(d for d in dirs
                         if os.path.realpath(os.path.join(root, d)) != out_real)
        for d in list(dirs):
            label = next((l for ext, l in FOLDER_FORMATS if d.lower().endswith(ext)), None)
            if label:
                path = os.path.join(root, d)
                volumes.append({"name": os.path.relpath(path, input_dir), "format": label,
                                "files": [path]})
                dirs.remove(d)
        tiff_groups = {}
        for f in sorted(files):
            ext, label = _format_of(f)
            if ext is None:
                ignored += 1
                continue
            path = os.path.join(root, f)
            rel = os.path.relpath(path, input_dir)
            if label == "TIFF":  # never OME-TIFF: its planes are in one file or named in it
                m = re.match(r"^(.*?)(\d+)(\.tiff?)$", f, re.IGNORECASE)
                key = (m.group(1), m.group(3).lower()) if m else (f, "")
                tiff_groups.setdefault(key, []).append(path)
                continue
            volumes.append({"name": rel, "format": label, "files": [path]})
        for (prefix, ext), paths in sorted(tiff_groups.items()):
            if len(paths) == 1:
                rel = os.path.relpath(paths[0], input_dir)
                volumes.append({"name": rel, "format": "TIFF", "files": paths})
            else:
                # Numeric order (slice_2 before slice_10), not string order.
                paths.sort(key=lambda p: int(re.search(r"(\d+)\.tiff?$", p, re.I).group(1)))
                rel = os.path.relpath(os.path.join(root, prefix + "*" + ext), input_dir)
                volumes.append({"name": rel, "format": "TIFF stack", "files": paths})
    volumes.sort(key=lambda v: v["name"])
    seen = {}
    for v in volumes:
        vid = _volume_id(v["name"])
        seen[vid] = seen.get(vid, 0) + 1
        v["id"] = vid if seen[vid] == 1 else "%s_%d" % (vid, seen[vid])
    return volumes, ignored


def _all_files(files):
    """The files themselves, and every file inside a folder volume (OME-Zarr)."""
    for f in files:
        if os.path.isdir(f):
            for root, _, names in os.walk(f):
                for n in names:
                    yield os.path.join(root, n)
        else:
            yield f


def transfer_function_signature(path):
    """{"file", "crc32"} of a transfer-function file (its bytes name its model and that
    model's checksum), or None without one: what a reused record must have been made with."""
    if not path:
        return None
    with open(path, "rb") as f:
        return {"file": os.path.abspath(path), "crc32": zlib.crc32(f.read()) & 0xFFFFFFFF}


def signature(files):
    """Total size and newest modification time of a volume's files: a changed file is
    redone on resume."""
    size, mtime = 0, 0
    for f in _all_files(files):
        st = os.stat(f)
        size += st.st_size
        mtime = max(mtime, st.st_mtime_ns)
    return [size, mtime]


def _write_json(path, data):
    """Write to a temporary name, then rename: an interrupted write leaves no record, and a
    failed one (disk full: OSError, raised) no temporary file."""
    tmp = path + ".part"
    try:
        with open(tmp, "w") as f:
            json.dump(data, f, indent=2)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


# ------------------------------------------------------------------------------------
# Worker: one volume, in its own pvbatch process.


class VolumeError(Exception):
    pass


def _read(simple, spec):
    """The reader of the volume, updated."""
    files = spec["files"]
    if spec["format"] == "TIFF stack":
        reader = simple.CheckedTIFFReader(FileNames=files)  # slices of one volume, in order
    else:
        try:
            reader = simple.OpenDataFile(files[0])
        except RuntimeError as exc:  # every reader's CanReadFile said no
            raise VolumeError("no reader accepts this file (corrupt or not a volume): %s"
                              % str(exc).strip())
        if reader is None:
            raise VolumeError("ParaView has no reader for this file")
    reader.UpdatePipeline()
    return reader


def _open_volume(simple, spec):
    watcher = B.VtkErrors()  # the reader's reason when it refuses the file
    try:
        reader = _read(simple, spec)
    finally:
        watcher.stop()
    errors = watcher.take()
    data = reader.GetClientSideObject().GetOutputDataObject(0)
    if data is None or not data.IsA("vtkImageData"):
        raise VolumeError("the reader gave %s, not image data"
                          % (data.GetClassName() if data is not None else "nothing"))
    if data.GetNumberOfPoints() < 2:
        raise VolumeError("the reader produced no voxels: %s" % (
            errors[0] if errors else "unreadable or corrupt file"))
    channels = channel_arrays(data)
    if not channels:
        raise VolumeError("the file holds no voxel values (no point data array)")
    scalars = data.GetPointData().GetScalars()
    if scalars is None or scalars.GetName() not in [c.GetName() for c in channels]:
        scalars = channels[0]
    return reader, data, scalars


def channel_arrays(data):
    """The named point arrays of the volume that are channels, in file order."""
    pd = data.GetPointData()
    arrays = [pd.GetArray(i) for i in range(pd.GetNumberOfArrays())]
    return [a for a in arrays if a is not None and a.GetName()
            and a.GetName() not in INTERNAL_ARRAYS]


def channel_colors(data, count):
    """The channels' display colours: the file's (field data ChannelColors, hex RGB as
    OME-Zarr's omero and OME-TIFF give them), else ImageJ's composite order."""
    colors = [CHANNEL_COLORS[i % len(CHANNEL_COLORS)] for i in range(count)]
    given = data.GetFieldData().GetAbstractArray("ChannelColors")
    if given is not None and given.GetNumberOfValues() == count:
        for i in range(count):
            text = str(given.GetValue(i)).strip().lstrip("#")
            if re.match(r"^[0-9A-Fa-f]{6}([0-9A-Fa-f]{2})?$", text):
                colors[i] = tuple(int(text[k:k + 2], 16) / 255.0 for k in (0, 2, 4))
    return colors


def composite_source(simple, data, channels, colors):
    """A source of the volume's channel composite: a uint8 RGBA array ChannelComposite
    (each channel from black to its colour over its percentile ramp, the colours added,
    alpha the largest normalised channel) and the same alpha as float CompositeOpacity
    (what the best viewpoint looks at). Returns (source, ramps)."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData

    rgb = np.zeros((data.GetNumberOfPoints(), 3))
    alpha = np.zeros(data.GetNumberOfPoints())
    ramps = []
    for array, color in zip(channels, colors):
        low, high = robust_ramp(array)
        ramps.append([low, high])
        values = vtk_to_numpy(array).astype(np.float64).reshape(-1)
        level = np.clip((values - low) / (high - low if high > low else 1.0), 0.0, 1.0)
        level[~np.isfinite(level)] = 0.0
        rgb += level[:, None] * np.asarray(color)[None, :]
        alpha = np.maximum(alpha, level)
    rgba = np.empty((rgb.shape[0], 4), dtype=np.uint8)
    rgba[:, :3] = np.round(255 * np.clip(rgb, 0.0, 1.0))
    rgba[:, 3] = np.round(255 * alpha)
    # The ray caster scales each component by its own range before using it as a colour:
    # one transparent voxel that spans 0..255 in R, G and B keeps the colours as they are.
    rgba[0, :3] = 255
    rgba[0, 3] = 0
    image = vtkImageData()
    image.CopyStructure(data)
    composite = numpy_to_vtk(rgba, deep=True)
    composite.SetName("ChannelComposite")
    image.GetPointData().AddArray(composite)
    opacity = numpy_to_vtk(alpha.astype(np.float32), deep=True)
    opacity.SetName("CompositeOpacity")
    image.GetPointData().AddArray(opacity)
    producer = simple.PVTrivialProducer()
    producer.GetClientSideObject().SetOutput(image)
    producer.UpdatePipeline()
    return producer, ramps


def robust_ramp(scalars, low_percentile=1.0, high_percentile=99.5):
    """The ramp a user would set by hand: from the 1st to the 99.5th percentile of the
    non-empty voxels (those above the volume's minimum, usually the background), so that a
    long bright tail (a few vessels or artefacts at 10x the tissue) does not leave the
    anatomy black. Falls back to the full range when the percentiles coincide."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    values = vtk_to_numpy(scalars).astype(np.float64).ravel()
    values = values[np.isfinite(values)]
    lowest, highest = float(values.min()), float(values.max())
    filled = values[values > lowest]
    if filled.size < 2:
        return lowest, highest
    low, high = (float(v) for v in np.percentile(filled, [low_percentile, high_percentile]))
    if not high > low:
        return lowest, highest
    return low, high


def _apply_transfer_function(mce, reader, view, spec, record):
    """The volume through the transfer-function file: the file's model applied (no fit)
    and its widgets shown; the out-of-model share into the record. Returns (source, best
    viewpoint properties)."""
    try:
        reduction, display = mce.apply_transfer_function(reader, spec["transfer_function"],
                                                         view)
    except ValueError as exc:  # a missing channel, a bad file: the reason is the entry
        raise VolumeError(str(exc))
    reduction.UpdatePropertyInformation()
    outside = int(reduction.GetProperty("NumberOfOutOfModelVoxels").GetElement(0))
    voxels = int(reduction.GetDataInformation().GetNumberOfPoints())
    record["out_of_model_voxels"] = outside
    record["voxels"] = voxels
    record["out_of_model_share"] = outside / float(voxels) if voxels else 0.0
    record["representation"] = display.SMProxy.GetProperty("Representation").GetElement(0)
    return reduction, {}


def run_worker(spec_json):
    """Renders one volume; writes its thumbnail, then its record (the record last, so a
    record on disk means the volume is finished). Returns the process exit code."""
    spec = json.loads(spec_json)
    _die_with_parent(spec.get("driver"))
    start = time.time()
    record = {
        "version": RECORD_VERSION, "name": spec["name"], "id": spec["id"],
        "format": spec["format"], "files": len(spec["files"]),
        "signature": signature(spec["files"]), "status": "error",
        "transfer_function": spec.get("transfer_function_signature"),
    }
    try:
        from paraview import simple

        mce = load_plugin(spec.get("plugin"))
        reader, data, scalars = _open_volume(simple, spec)
        channels = channel_arrays(data)
        times = list(getattr(reader, "TimestepValues", None) or [])
        record["time_steps"] = len(times) if len(times) > 1 else 1
        record["channel_list"] = [{
            "name": a.GetName(), "scalar_type": a.GetDataTypeAsString(),
            "components": a.GetNumberOfComponents(),
            "range": [float(x) for x in a.GetRange(0)]} for a in channels]
        unit = data.GetFieldData().GetAbstractArray("LengthUnit")
        if unit is not None and unit.GetNumberOfValues() > 0:
            record["unit"] = str(unit.GetValue(0))
        composite = len(channels) > 1 and all(a.GetNumberOfComponents() == 1 for a in channels)
        ncomp = scalars.GetNumberOfComponents()
        array = scalars.GetName()
        source = reader
        if ncomp > 1 and not composite:
            # A 4D / multi-component volume: its first component (see the docstring).
            source = simple.ExtractComponent(Input=reader, InputArray=["POINTS", array],
                                             Component=0, OutputArrayName=array + "_0")
            source.UpdatePipeline()
            array = array + "_0"
            scalars = source.GetClientSideObject().GetOutputDataObject(0) \
                .GetPointData().GetArray(array)
        record.update({
            "dimensions": list(data.GetDimensions()),
            "spacing": [float(s) for s in data.GetSpacing()],
            "origin": [float(s) for s in data.GetOrigin()],
            "scalar_type": scalars.GetDataTypeAsString(),
            "components": ncomp,
            "component_used": 0 if ncomp > 1 and not composite else None,
            "array": array,
            "range": [float(x) for x in scalars.GetRange(0)],
        })
        if all(c["range"][1] <= c["range"][0] for c in record["channel_list"]) or \
                record["range"][1] <= record["range"][0] and not composite:
            raise VolumeError("constant volume (all voxels %g): nothing to see"
                              % record["range"][0])

        view = render_view(spec["size"])
        if spec.get("transfer_function"):
            source, view_properties = _apply_transfer_function(mce, reader, view, spec, record)
        elif composite:
            colors = channel_colors(data, len(channels))
            source, ramps = composite_source(simple, data, channels, colors)
            for entry, color, ramp in zip(record["channel_list"], colors, ramps):
                entry["color"] = "#%02x%02x%02x" % tuple(int(round(255 * c)) for c in color)
                entry["ramp"] = ramp
            record["composite"] = True
            display = simple.Show(source, view)
            display.SetRepresentationType("Volume")
            simple.ColorBy(display, ("POINTS", "ChannelComposite"))
            display.MapScalars = 0  # the RGB components are the colours
            display.MultiComponentsMapping = 1  # ... and the 4th goes through the opacity
            pwf = simple.GetOpacityTransferFunction("ChannelComposite")
            # At most a quarter opaque per voxel: a channel that fills the outside (a T1's
            # skin, a membrane stain) lets the channels inside show through. ParaView
            # 5.11's volume representation has no maximum intensity projection.
            pwf.Points = [0.0, 0.0, 0.5, 0.0, 255.0, 0.25, 0.5, 0.0]
            opacity = simple.CreatePiecewiseFunction(Points=[0.0, 0.0, 0.5, 0.0,
                                                             1.0, 1.0, 0.5, 0.0])
            view_properties = {"Channels": ["CompositeOpacity"], "OpacityFunction": opacity}
        else:
            display = simple.Show(source, view)
            display.SetRepresentationType("Volume")
            simple.ColorBy(display, ("POINTS", array))
            low, high = robust_ramp(scalars)
            record["ramp"] = [low, high]
            lut = simple.GetColorTransferFunction(array)
            lut.ApplyPreset("Grayscale", True)
            lut.RescaleTransferFunction(low, high)
            pwf = simple.GetOpacityTransferFunction(array)
            pwf.Points = [low, 0.0, 0.5, 0.0, high, 1.0, 0.5, 0.0]
            view_properties = {}

        best = mce.apply_best_viewpoint(source, view, which="best", disambiguate=True,
                                        **view_properties)
        if not best.valid:
            raise VolumeError("no best viewpoint: flat or constant opacity")
        B.checked_png(spec["thumbnail"], lambda path: simple.SaveScreenshot(path, view),
                      spec["size"])
        stats = mce.image_statistics(spec["thumbnail"])
        timings = [float(x) for x in best.filter.GetPropertyValue("StageTimings")]
        record.update({
            "status": "ok",
            "best_direction": [float(x) for x in best.direction],
            "view_up": [float(x) for x in best.view_up],
            "eigenvalues": [float(x) for x in best.eigenvalues],
            "device": best.device,
            "interest_points": best.filter.GetDataInformation().GetNumberOfPoints(),
            "viewpoint_ms": timings[3] if len(timings) > 3 else None,
            "thumbnail": os.path.relpath(spec["thumbnail"], spec["output"]),
            "thumbnail_stddev": stats["stddev"],
        })
    except Exception as exc:  # any failure becomes this volume's error entry
        record["status"] = "error"
        record["error"] = "%s: %s" % (type(exc).__name__, exc) \
            if not isinstance(exc, (VolumeError, B.JobError)) else str(exc)
        if isinstance(exc, OSError) or isinstance(exc, B.JobError):
            environment = _environment_failure(spec["output"])
            if environment:
                record["environment"] = environment
    record["seconds"] = round(time.time() - start, 3)
    record["finished"] = time.strftime("%Y-%m-%d %H:%M:%S")
    try:
        _write_json(spec["record"], record)
    except OSError as exc:  # the driver finds the cause with its own probe write
        sys.stderr.write("ERROR: record not written: %s\n" % B.cause_of(exc))
        return 3
    return 0


# ------------------------------------------------------------------------------------
# Driver: discovery, resume, one worker per volume, progress, index.

_ANSI = re.compile(r"\x1b\[[0-9;]*m")


def _error_lines(stderr, limit=3):
    """The VTK/ParaView error messages of a worker's stderr (ERR| lines), trimmed."""
    out = []
    for line in _ANSI.sub("", stderr or "").splitlines():
        if "ERR|" in line:
            text = line.split("ERR|", 1)[1].strip()
            text = re.sub(r"\s*\(0x[0-9a-f]+\)", "", text)
            if text and text not in out:
                out.append(text)
        elif line.startswith("ERROR:") or line.startswith("Traceback"):
            out.append(line.strip())
    return out[:limit]


def _pvbatch():
    """The running pvbatch (sys.executable is not it inside pvbatch)."""
    exe = os.path.realpath("/proc/self/exe") if os.path.exists("/proc/self/exe") else None
    if exe and os.path.basename(exe).startswith(("pvbatch", "pvpython")):
        return exe
    return shutil.which("pvbatch") or sys.exit("pvbatch not found")


def process_volume(vol, args, paths):
    """Runs a worker for one volume under the time limit; returns its record. The worker
    writes a new thumbnail and record beside the old ones (staged_paths); they replace the
    old ones only when the thumbnail decodes (commit_volume): a forced redo that is
    interrupted, or fails for want of disk room, leaves the previous snapshot as it was."""
    staged = staged_paths(vol, paths)
    spec = {
        "name": vol["name"], "id": vol["id"], "format": vol["format"],
        "files": [os.path.abspath(f) for f in vol["files"]],
        "thumbnail": staged["thumbnail"], "record": staged["record"],
        "output": paths["output"], "size": list(args.size), "plugin": args.plugin,
        "driver": os.getpid(), "transfer_function": args.transfer_function,
        "transfer_function_signature": paths.get("transfer_function"),
    }
    remove_staged(staged)
    start = time.time()
    cmd = [_pvbatch(), THIS, "--worker", json.dumps(spec)]
    try:
        # A worker killed by a signal is tried twice more: on shared, loaded machines the X
        # server of xvfb-run is sometimes gone for a moment ("bad X server connection"),
        # which is no fault of the file. A reader that crashes on the file crashes thrice.
        for attempt in (1, 2, 3):
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                    universal_newlines=True, start_new_session=True)
            try:
                stdout, stderr = proc.communicate(timeout=args.timeout)
                problem = None if proc.returncode == 0 else (
                    "the worker died (%s)" % ("signal %d" % -proc.returncode
                                              if proc.returncode < 0
                                              else "exit code %d" % proc.returncode))
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)  # the worker's own session only
                stdout, stderr = proc.communicate()
                problem = "timed out after %g s" % args.timeout
            except BaseException:  # SIGINT / SIGTERM of this run: the worker goes too
                _kill_worker(proc)
                raise
            if problem is None or problem.startswith("timed out"):
                break
            if _environment_failure(paths["output"]):
                break  # no room to write: trying again would fail the same way
        wall = round(time.time() - start, 3)
        messages = _error_lines(stderr)
        record = None
        if problem is None and os.path.exists(staged["record"]):
            with open(staged["record"]) as f:
                record = json.load(f)
        if record is None:
            record = {"version": RECORD_VERSION, "name": vol["name"], "id": vol["id"],
                      "format": vol["format"], "files": len(vol["files"]),
                      "signature": signature(vol["files"]), "status": "error",
                      "transfer_function": paths.get("transfer_function"),
                      "error": problem or "the worker wrote no record",
                      "finished": time.strftime("%Y-%m-%d %H:%M:%S")}
            environment = _environment_failure(paths["output"])
            if environment:
                record["environment"] = environment
        if record["status"] != "ok" and messages:
            record["messages"] = messages
        record["wall_seconds"] = wall
        return commit_volume(record, staged, paths)
    finally:
        remove_staged(staged)


# ------------------------------------------------------------------------------------
# Writing, locking, run state and signals of the driver: a volume's new snapshot replaces
# the old one only once it is complete and checked; an error that is not the file's fault
# (disk full, read-only folder, the run interrupted) keeps the old snapshot, stops the run
# and is tried again on the next run; one run at a time per output folder.

class StopRun(Exception):
    """The run cannot go on: disk full, read-only or unwritable output folder."""


def staged_paths(vol, paths):
    """Where the worker writes a volume's new thumbnail and record (hidden names beside the
    final ones; leftovers of a killed run are removed by the next one)."""
    return {"thumbnail": os.path.join(paths["thumbnails"], "." + vol["id"] + ".new.png"),
            "record": os.path.join(paths["records"], "." + vol["id"] + ".new.json"),
            "final_thumbnail": os.path.join(paths["thumbnails"], vol["id"] + ".png"),
            "final_record": os.path.join(paths["records"], vol["id"] + ".json")}


def remove_staged(staged):
    for key in ("thumbnail", "record"):
        for path in (staged[key], staged[key] + ".part", staged[key] + ".part.png",
                     os.path.join(os.path.dirname(staged[key]),
                                  "." + os.path.basename(staged[key]) + ".part.png")):
            if os.path.exists(path):
                os.remove(path)


def remove_stale_staging(paths):
    """Staged files of runs that were killed (the lock says no run is writing)."""
    for sub in ("thumbnails", "records"):
        for name in os.listdir(paths[sub]):
            if name.startswith(".") and (".new." in name or name.endswith(".part")):
                os.remove(os.path.join(paths[sub], name))


def _environment_failure(output):
    """'disk full', 'read-only file system', 'permission denied' when a probe write into
    the output folder fails so, else None."""
    exc = B.probe_write(output)
    return B.cause_of(exc) if exc is not None else None


def _die_with_parent(driver):
    """In the worker, first thing: SIGKILL when the driver (pid `driver`) dies (prctl
    PR_SET_PDEATHSIG), so that a killed run leaves no worker writing behind it; a driver
    already gone ends the worker at once. Called in the worker rather than as Popen's
    preexec_fn, which is not safe in a process with threads (pvbatch has them)."""
    try:
        import ctypes
        ctypes.CDLL(None).prctl(1, signal.SIGKILL)
    except (OSError, AttributeError):
        return
    if driver and os.getppid() != driver:
        os._exit(1)


def _kill_worker(proc):
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except OSError:
        pass
    proc.wait()


def commit_volume(record, staged, paths):
    """Puts a volume's new record (and thumbnail, when it succeeded) in place of the old
    ones; returns the record. A thumbnail that does not decode makes the record an error.
    A failure that is not the file's fault (record["environment"]) leaves the old record
    and thumbnail as they were and raises StopRun."""
    if record.get("environment"):
        raise StopRun(record["environment"])
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        if record["status"] == "ok":
            problem = B.check_png(staged["thumbnail"])
            if problem:
                record = dict(record, status="error",
                              error="the thumbnail %s" % problem)
                record.pop("thumbnail", None)
            else:
                record["thumbnail"] = os.path.relpath(staged["final_thumbnail"],
                                                      paths["output"])
                record["thumbnail_bytes"] = os.path.getsize(staged["thumbnail"])
                record["thumbnail_size"] = paths.get("size")
        try:
            if record["status"] == "ok":
                os.replace(staged["thumbnail"], staged["final_thumbnail"])
            _write_json(staged["final_record"], record)
        except OSError as exc:
            raise StopRun(B.cause_of(exc))
        if record["status"] != "ok" and os.path.exists(staged["final_thumbnail"]):
            os.remove(staged["final_thumbnail"])  # no failed volume looks finished
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)
    return record


def lock_output(paths):
    """An exclusive lock on the output folder for this run (B.lock_file: a second run stops
    with a message naming the first one's pid)."""
    return B.lock_file(os.path.join(paths["output"], ".lock"),
                       "the snapshot folder %s" % paths["output"])


def _raise_interrupted(signum, frame):
    raise B.Interrupted(signum)


def catch_stop_signals():
    """SIGINT / SIGTERM raise B.Interrupted in the driver: the running worker is killed, its
    staged files removed, the index says the run was interrupted, exit 130 / 143."""
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, _raise_interrupted)


def index_entries(volumes, records, paths, stored=None):
    """Every volume of the folder, in order: this run's record, else the stored one that is
    still valid (from `stored`, name -> record, when given: read once at the run's start),
    else {"status": "pending"} (not yet tried)."""
    done = {r["name"]: r for r in records}
    entries = []
    for vol in volumes:
        r = done.get(vol["name"]) or (stored.get(vol["name"]) if stored is not None
                                      else load_finished(vol, paths))
        if r is None:
            r = {"name": vol["name"], "id": vol["id"], "format": vol["format"],
                 "status": "pending"}
        entries.append(r)
    return entries


def run_summary(entries, state):
    """'7 of 8 done, run interrupted (SIGINT)': done, failed and not tried counted over
    every volume of the folder, and how the run ended (or that it is running)."""
    ok = sum(1 for r in entries if r["status"] == "ok")
    failed = sum(1 for r in entries if r["status"] == "error")
    pending = sum(1 for r in entries if r["status"] == "pending")
    text = "%d of %d done" % (ok, len(entries))
    if failed:
        text += ", %d failed" % failed
    if pending:
        text += ", %d not yet tried" % pending
    return text + ", run " + state


def load_finished(vol, paths):
    """The stored record of a volume when it can be reused, else None."""
    record_path = os.path.join(paths["records"], vol["id"] + ".json")
    try:
        with open(record_path) as f:
            record = json.load(f)
    except (OSError, ValueError):
        return None
    if record.get("version") != RECORD_VERSION or record.get("name") != vol["name"]:
        return None
    if record.get("transfer_function") != paths.get("transfer_function"):
        return None  # made with another transfer function, or without this one
    try:
        if record.get("signature") != signature(vol["files"]):
            return None  # the file changed since
    except OSError:
        return None
    if record.get("status") == "ok":
        thumbnail = os.path.join(paths["output"], record.get("thumbnail", ""))
        if not os.path.isfile(thumbnail):
            return None
        if "thumbnail_bytes" in record and os.path.getsize(thumbnail) != record["thumbnail_bytes"]:
            return None  # a thumbnail of another render than the record's (a cut commit)
        if record.get("thumbnail_size") != paths.get("size"):
            return None  # rendered at another --size
    return record


def progress(done, total, name, status=""):
    filled = int(round(BAR_WIDTH * done / float(total))) if total else BAR_WIDTH
    return "[%s%s] %d/%d %s%s" % ("#" * filled, " " * (BAR_WIDTH - filled), done, total,
                                  name, ("  " + status) if status else "")


def _vec(v, fmt="%+.3f"):
    return "(" + ", ".join(fmt % x for x in v) + ")" if v else ""


def write_index(records, paths, input_dir, started, state="complete"):
    """index.json and index.html of `records` (every volume of the folder: index_entries),
    with the run's `state` ("complete", "in progress (pid N)", "interrupted (SIGINT)",
    "stopped: disk full") in the summary."""
    with B.signals_held():  # no index.json.part left behind by a signal
        _write_index(records, paths, input_dir, state)


def _write_index(records, paths, input_dir, state):
    ok = sum(1 for r in records if r["status"] == "ok")
    summary = run_summary(records, state)
    index = {"input": os.path.abspath(input_dir), "generated": time.strftime("%Y-%m-%d %H:%M:%S"),
             "succeeded": ok, "total": len(records), "run": state, "summary": summary,
             "failed": sum(1 for r in records if r["status"] == "error"),
             "not_tried": sum(1 for r in records if r["status"] == "pending"),
             "volumes": records}
    _write_json(os.path.join(paths["output"], "index.json"), index)

    e = html.escape
    cards = []
    for r in records:
        rows = [("format", r.get("format", ""))]
        if "dimensions" in r:
            rows.append(("dimensions", " &times; ".join(str(d) for d in r["dimensions"])))
            rows.append(("spacing", e(_vec(r["spacing"], "%.4g") + (
                " " + r["unit"] if r.get("unit") else ""))))
            comp = ""
            if r.get("components", 1) > 1:
                comp = " (component %d of %d)" % (r["component_used"], r["components"])
            if len(r.get("channel_list", [])) > 1:
                rows.append(("channels", "<br>".join(
                    '%s<b>%s</b> %s, %.6g .. %.6g' % (
                        '<span class="swatch" style="background:%s"></span>' % c["color"]
                        if c.get("color") else "", e(c["name"]), e(c["scalar_type"]),
                        c["range"][0], c["range"][1]) for c in r["channel_list"])))
            else:
                rows.append(("scalars", e("%s%s, range %.6g .. %.6g%s" % (
                    r["array"] + ": " if r.get("array") else "", r["scalar_type"],
                    r["range"][0], r["range"][1], comp))))
            if r.get("time_steps", 1) > 1:
                rows.append(("time steps", "%d (the first shown)" % r["time_steps"]))
        if r["status"] == "pending":
            rows.append(("state", "not yet tried"))
            image = '<div class="noimage">not yet tried</div>'
        elif r["status"] == "ok":
            if r.get("transfer_function"):
                rows.append(("transfer function", e(os.path.basename(
                    r["transfer_function"]["file"]))))
                rows.append(("out of model", e("%.2f%% of the voxels (%d of %d)" % (
                    100.0 * r["out_of_model_share"], r["out_of_model_voxels"],
                    r["voxels"]))))
            rows.append(("best direction", e(_vec(r["best_direction"]))))
            eig = r["eigenvalues"]
            bars = "".join(
                '<span class="bar" style="width:%dpx" title="&lambda;%d = %.4f"></span>'
                % (max(1, int(round(120 * x))), i + 1, x) for i, x in enumerate(eig))
            rows.append(("eigenvalues", "%s<br>%s" % (e(_vec(eig, "%.3f")), bars)))
            rows.append(("time", e("%.1f s (%s, %d interest points)" % (
                r.get("wall_seconds", r["seconds"]), r["device"], r["interest_points"]))))
            image = '<img src="%s" alt="%s">' % (e(r["thumbnail"]), e(r["name"]))
        else:
            text = r.get("error", "error")
            if r.get("messages"):
                text += "\n" + "\n".join(r["messages"])
            rows.append(("error", '<pre class="error">%s</pre>' % e(text)))
            if "wall_seconds" in r:
                rows.append(("time", "%.1f s" % r["wall_seconds"]))
            image = '<div class="noimage">no snapshot</div>'
        table = "".join("<tr><th>%s</th><td>%s</td></tr>" % (k, v) for k, v in rows)
        cards.append('<div class="card %s">%s<h2>%s</h2><table>%s</table></div>' % (
            r["status"], image, e(r["name"]), table))
    page = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>Volume snapshots: %(input)s</title>
<style>
body{font-family:sans-serif;background:#f4f4f4;margin:1em}
.card{display:inline-block;vertical-align:top;width:340px;margin:6px;padding:8px;background:#fff;
 border:1px solid #ccc;border-radius:4px}
.card.error{border-color:#c33}
.card img{width:320px;display:block}
.noimage{width:320px;height:120px;line-height:120px;text-align:center;background:#eee;color:#888}
h2{font-size:14px;word-break:break-all;margin:6px 0}
table{font-size:12px;border-collapse:collapse}
th{text-align:left;padding-right:8px;vertical-align:top;color:#555;font-weight:normal}
.bar{display:inline-block;height:8px;background:#4a7;margin-right:3px}
.swatch{display:inline-block;width:10px;height:10px;margin-right:4px;border:1px solid #888}
pre.error{color:#b00;white-space:pre-wrap;margin:0;font-size:11px}
</style></head><body>
<h1>Volume snapshots</h1>
<p>%(summary)s &mdash; folder <code>%(input)s</code>, generated %(generated)s.
Each thumbnail is the best viewpoint (camera along v3 of the 3D Harris interest points);
the eigenvalues are the normalised PCA spectrum of those points.</p>
%(cards)s
</body></html>
""" % {"input": e(os.path.abspath(input_dir)), "generated": index["generated"],
       "summary": e(summary),
       "cards": "\n".join(cards)}
    B.write_text(os.path.join(paths["output"], "index.html"), page)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--input", required=False, help="folder of volumes (recursive)")
    parser.add_argument("--output", required=False, help="folder for index and thumbnails")
    parser.add_argument("--force", nargs="*", default=None, metavar="NAME",
                        help="redo all volumes, or only the NAMEs given")
    parser.add_argument("--retry-failed", action="store_true",
                        help="try again the volumes that failed in an earlier run")
    parser.add_argument("--timeout", type=float, default=600.0,
                        help="seconds allowed per volume (default 600)")
    parser.add_argument("--size", type=int, nargs=2, default=[400, 400], metavar=("W", "H"),
                        help="thumbnail size in pixels (default 400 400)")
    parser.add_argument("--plugin", default=None, help="MultichannelExplorer plugin library")
    parser.add_argument("--transfer-function", default=None, metavar="FILE.mcvtf",
                        help="render every volume with this transfer-function file (its "
                        "reduction model applied, its Gaussian widgets), so that colours "
                        "mean the same in every thumbnail")
    parser.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker is not None:
        return run_worker(args.worker)
    if not args.input or not args.output:
        parser.error("--input and --output are required")
    if not os.path.isdir(args.input):
        print("input folder not found: %s" % args.input)
        return 1
    if args.plugin is None:
        # Resolve it once here so every worker loads the same library.
        from example_support import find_plugin
        if not os.environ.get("PV_PLUGIN_PATH"):
            args.plugin = find_plugin()

    paths = {"output": os.path.abspath(args.output), "size": list(args.size)}
    if args.transfer_function:
        # Checked once, before any volume: a bad file (or a missing model) stops the run.
        args.transfer_function = os.path.abspath(args.transfer_function)
        try:
            load_plugin(args.plugin).read_transfer_function(args.transfer_function)
            paths["transfer_function"] = transfer_function_signature(args.transfer_function)
        except (ValueError, OSError) as exc:
            print("error: %s" % exc)
            return 1
    try:
        for sub in ("thumbnails", "records"):
            paths[sub] = os.path.join(paths["output"], sub)
            os.makedirs(paths[sub], exist_ok=True)
        lock = lock_output(paths)
    except (OSError, B.JobError) as exc:
        print("error: %s" % (exc if isinstance(exc, B.JobError) else
                             "cannot write into %s: %s" % (paths["output"], B.cause_of(exc))))
        return 1
    catch_stop_signals()
    try:
        remove_stale_staging(paths)
        started = time.time()
        volumes, ignored = discover(args.input, args.output)
        print("%d volumes in %s%s" % (len(volumes), args.input,
                                       " (%d other files ignored)" % ignored if ignored else ""))
        sys.stdout.flush()
        return drive(volumes, args, paths, started)
    except B.Interrupted as exc:  # before the first volume: nothing written, the index as it was
        print("interrupted (%s) before any volume was done" % signal.Signals(exc.signum).name)
        return exc.exit_code
    finally:
        lock.close()


def drive(volumes, args, paths, started):
    """The run over `volumes`: resume, one worker per volume, progress, the index after each
    (with every volume of the folder and the run's state). Returns the exit code: 0 when at
    least one volume has a snapshot, 1 when none or when the run had to stop (disk full,
    read-only folder), 130 / 143 on SIGINT / SIGTERM."""
    total = len(volumes)
    if not total:
        write_index([], paths, args.input, started)
        print("0 of 0 volumes succeeded")
        return 1
    force_all = args.force is not None and len(args.force) == 0
    force_names = set(args.force or [])
    unknown = force_names - {v["name"] for v in volumes}
    if unknown:
        print("--force: no such volume: %s" % ", ".join(sorted(unknown)))

    records, processed, skipped = [], 0, 0
    state, code = "complete", None
    try:
        stored = {v["name"]: load_finished(v, paths) for v in volumes}
        write_index(index_entries(volumes, records, paths, stored), paths, args.input,
                    started, "in progress (pid %d)" % os.getpid())
        for i, vol in enumerate(volumes):
            forced = force_all or vol["name"] in force_names
            record = None if forced else load_finished(vol, paths)
            if record is not None and record["status"] != "ok" and (
                    args.retry_failed or record.get("environment")):
                record = None  # a disk-full failure is no fault of the file: tried again
            if record is not None:
                skipped += 1
                status = "skipped (%s before)" % ("done" if record["status"] == "ok"
                                                  else "failed")
            else:
                if sys.stdout.isatty():  # a live line on a terminal, not in logs
                    sys.stdout.write(progress(i, total, vol["name"], "...") + "\r")
                    sys.stdout.flush()
                record = process_volume(vol, args, paths)
                processed += 1
                if record["status"] == "ok":
                    status = "ok %.1f s" % record["wall_seconds"]
                else:
                    status = "FAILED: %s" % record.get("error", "")
            records.append(record)
            print(progress(i + 1, total, vol["name"], status))
            sys.stdout.flush()
            # A partial index survives a stop, and says the run is not finished.
            write_index(index_entries(volumes, records, paths, stored), paths, args.input,
                        started, "in progress (pid %d)" % os.getpid() if i + 1 < total
                        else state)
    except B.Interrupted as exc:
        state, code = "interrupted (%s)" % signal.Signals(exc.signum).name, exc.exit_code
    except (StopRun, B.JobError, OSError) as exc:
        cause = B.cause_of(exc) if isinstance(exc, OSError) else str(exc)
        state, code = "stopped: %s" % cause, 1
        if cause.startswith("disk"):
            state += " (%s free; the volumes not done are tried again on the next run)" % (
                B._human(B.free_bytes(paths["output"])))
    if code is not None:
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        entries = index_entries(volumes, records, paths)
        summary = run_summary(entries, state)
        try:
            write_index(entries, paths, args.input, started, state)
        except (OSError, B.JobError) as exc:
            print("the index could not be updated (%s): it still says the run is in "
                  "progress" % B.cause_of(exc) if isinstance(exc, OSError) else exc)
        print(summary)
        print("%d of %d volumes succeeded" % (
            sum(1 for r in entries if r["status"] == "ok"), total))
        return code

    ok = sum(1 for r in records if r["status"] == "ok")
    print("index: %s (and index.json); %d processed, %d skipped, %.1f s" % (
        os.path.join(paths["output"], "index.html"), processed, skipped,
        time.time() - started))
    print("%d of %d volumes succeeded" % (ok, total))
    return 0 if ok > 0 else 1


if __name__ == "__main__":
    code = main(sys.argv[1:])
    sys.stdout.flush()
    sys.stderr.flush()
    # os._exit: pvbatch's own exit path must not turn the exit code into 0.
    os._exit(code)
