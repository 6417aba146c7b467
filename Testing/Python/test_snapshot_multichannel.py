"""Examples/snapshot_collection.py on a microscopist's own files: ImageJ hyperstacks,
OME-TIFF and OME-Zarr written here with tifffile and zarr from the real 3-channel brain
(Colin27 T1, AAL and Brodmann atlases, every 2nd voxel per axis).

Known answers:
  - every file gives a snapshot, and its record lists every channel by name (C1..C3 for a
    hyperstack without labels, the OME channel names, OME-Zarr's omero labels), with each
    channel's range equal to the source's;
  - a multichannel file is drawn as a channel composite: a hyperstack whose only non-zero
    channel is C2 comes out green (ImageJ's C2 colour), an OME-Zarr whose only non-zero
    channel has the omero colour FF00FF comes out magenta, and the 3-channel brain shows
    more than one hue;
  - a 2-frame hyperstack is recorded with 2 time steps.
"""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
checker = T.Checker("test_snapshot_multichannel")
SCRIPT = os.path.join(T.REPO, "Examples", "snapshot_collection.py")
PVBATCH = os.path.realpath("/proc/self/exe")

import numpy as np  # noqa: E402
import tifffile  # noqa: E402
import zarr  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402

NAMES = ("ch2", "aal", "brodmann")


brain = T.brain_arrays(NAMES, step=2).astype(np.uint16)  # (c, z, y, x)
zeros = np.zeros_like(brain[0])
print("channels", brain.shape, [int(c.max()) for c in brain])

work = os.path.join(T.output_dir(), "snapshot_multichannel")
shutil.rmtree(work, ignore_errors=True)
inp, out = os.path.join(work, "input"), os.path.join(work, "index")
os.makedirs(inp)

# ImageJ hyperstacks (axes ZCYX; TZCYX with a second frame).
zcyx = np.ascontiguousarray(brain.transpose(1, 0, 2, 3))
meta = {"axes": "ZCYX", "spacing": 2.0, "unit": "um"}
tifffile.imwrite(os.path.join(inp, "brain_hyperstack.tif"), zcyx, imagej=True,
                 resolution=(0.5, 0.5), metadata=meta)
green = np.stack([zeros, brain[0], zeros]).transpose(1, 0, 2, 3)
tifffile.imwrite(os.path.join(inp, "green_only.tif"), np.ascontiguousarray(green), imagej=True,
                 resolution=(0.5, 0.5), metadata=meta)
frames = np.stack([zcyx, zcyx // 2])
tifffile.imwrite(os.path.join(inp, "two_frames.tif"), frames, imagej=True,
                 resolution=(0.5, 0.5), metadata={"axes": "TZCYX", "spacing": 2.0,
                                                  "unit": "um", "finterval": 30.0})
# OME-TIFF with channel names.
tifffile.imwrite(os.path.join(inp, "brain.ome.tif"), brain, ome=True, metadata={
    "axes": "CZYX", "Channel": {"Name": list(NAMES)}, "PhysicalSizeX": 2.0,
    "PhysicalSizeY": 2.0, "PhysicalSizeZ": 2.0})


def write_zarr(path, channels, labels, colors):
    """An OME-Zarr (NGFF 0.4) image of one level, axes c, z, y, x."""
    root = zarr.open_group(zarr.DirectoryStore(path), mode="w")
    root.create_dataset("0", data=channels, chunks=(1, 32, 32, 32))
    axes = [{"name": "c", "type": "channel"}] + [
        {"name": a, "type": "space", "unit": "micrometer"} for a in "zyx"]
    root.attrs["multiscales"] = [{
        "version": "0.4", "axes": axes,
        "datasets": [{"path": "0", "coordinateTransformations": [
            {"type": "scale", "scale": [1.0, 2.0, 2.0, 2.0]}]}]}]
    root.attrs["omero"] = {"channels": [
        {"label": l, "color": c, "active": True} for l, c in zip(labels, colors)]}


write_zarr(os.path.join(inp, "brain.ome.zarr"), brain, NAMES, ("FF0000", "00FF00", "0000FF"))
write_zarr(os.path.join(inp, "magenta_only.ome.zarr"), np.stack([brain[0], zeros, zeros]),
           ("T1", "empty_a", "empty_b"), ("FF00FF", "00FF00", "00FFFF"))

cmd = [PVBATCH, SCRIPT, "--input", inp, "--output", out, "--size", "300", "300"]
run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                     universal_newlines=True, timeout=1800)
print(run.stdout[-3000:])
checker.check(run.returncode == 0, "snapshot tool exit code %d" % run.returncode)
with open(os.path.join(out, "index.json")) as f:
    index = json.load(f)
records = {r["name"]: r for r in index["volumes"]}
expected = {
    "brain_hyperstack.tif": ["C1", "C2", "C3"],
    "green_only.tif": ["C1", "C2", "C3"],
    "two_frames.tif": ["C1", "C2", "C3"],
    "brain.ome.tif": list(NAMES),
    "brain.ome.zarr": list(NAMES),
    "magenta_only.ome.zarr": ["T1", "empty_a", "empty_b"],
}
checker.check(sorted(records) == sorted(expected), "volumes found: %s" % sorted(records))


def hue_means(record):
    """Mean R, G, B of the thumbnail's pixels brighter than the background, how many
    there are, and how many of them each of R, G, B dominates."""
    reader = vtkPNGReader()
    reader.SetFileName(os.path.join(out, record["thumbnail"]))
    reader.Update()
    image = reader.GetOutput()
    rgb = vtk_to_numpy(image.GetPointData().GetScalars())[:, :3].astype(float)
    bright = rgb.max(axis=1) > 60
    dominant = np.bincount(rgb[bright].argmax(axis=1), minlength=3)
    return (rgb[bright].mean(axis=0) if bright.sum() > 100 else None, int(bright.sum()),
            dominant)


for name, names in expected.items():
    r = records.get(name)
    if r is None:
        continue
    ok = r["status"] == "ok"
    checker.check(ok, "%s: %s" % (name, "snapshot" if ok else r.get("error")))
    if not ok:
        continue
    got = [c["name"] for c in r.get("channel_list", [])]
    checker.check(got == names, "%s: channels listed by name %s (expected %s)"
                  % (name, got, names))
    checker.check(r.get("composite") is True, "%s: drawn as a channel composite" % name)
    source = {"green_only.tif": [zeros, brain[0], zeros],
              "magenta_only.ome.zarr": [brain[0], zeros, zeros]}.get(name, list(brain))
    if name == "two_frames.tif":
        checker.check(r.get("time_steps") == 2, "%s: 2 time steps recorded (%s)"
                      % (name, r.get("time_steps")))
    ranges = [c["range"] for c in r.get("channel_list", [])]
    want = [[float(s.min()), float(s.max())] for s in source]
    checker.check(ranges == want, "%s: channel ranges %s equal the source's %s"
                  % (name, ranges, want))
    means, n, dominant = hue_means(r)
    checker.check(means is not None, "%s: %d bright pixels in the thumbnail" % (name, n))
    if means is None:
        continue
    red, grn, blu = means
    print("%s: mean colour of %d bright pixels R %.0f G %.0f B %.0f; dominated by R, G, B: %s"
          % (name, n, red, grn, blu, list(dominant)))
    if name == "green_only.tif":
        checker.check(grn > 2 * red and grn > 2 * blu, "%s: green (C2's colour)" % name)
    elif name == "magenta_only.ome.zarr":
        checker.check(red > 2 * grn and blu > 2 * grn, "%s: magenta (omero colour FF00FF)"
                      % name)
    else:
        # Red (the T1, which holds the skin) is in front; the atlases inside show through.
        checker.check(sum(d >= 0.01 * n for d in dominant) >= 2,
                      "%s: more than one channel's colour shows (pixels dominated by R, G, B: "
                      "%s of %d)" % (name, list(dominant), n))

html = open(os.path.join(out, "index.html")).read()
for names in expected.values():
    for n in names:
        checker.check(">%s</b>" % n in html, "index.html lists channel %s" % n)
checker.finish()
