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
  - --transfer-function FILE.mcvtf (saved here from a PCA of the T1 + AAL brain, every 3rd
    voxel): the fit volume and one whose upper half changed are drawn as Gaussian TF
    Volumes with the file's model (records name the file; no voxel of the fit volume is
    out of the model, the changed one has some, and the index says so in its captions);
    a volume without the AAL channel is an error entry naming it, the run goes on; a second
    run reuses the snapshots, a run without the file redoes them; a bad file stops the
    run before any volume (exit code 1, its reason printed).
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


def hue_means(record, folder=None):
    """Mean R, G, B of the thumbnail's pixels brighter than the background, how many
    there are, and how many of them each of R, G, B dominates."""
    reader = vtkPNGReader()
    reader.SetFileName(os.path.join(folder or out, record["thumbnail"]))
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

# --- one transfer function for every volume ------------------------------------------------

tf_in, tf_out = os.path.join(work, "tf_input"), os.path.join(work, "tf_index")
os.makedirs(tf_in)


def write_vti(path, channels):
    return T.write_vti(path, channels)


small = T.brain_arrays(("ch2", "aal"), step=3).astype(np.float32)
t1, aal = small[0], small[1]
changed = t1.copy()
changed[t1.shape[0] // 2:] *= 1.3
fit_vti = write_vti(os.path.join(tf_in, "a_fit.vti"), [("ch2", t1), ("aal", aal)])
write_vti(os.path.join(tf_in, "b_changed.vti"), [("aal", aal), ("ch2", changed)])
write_vti(os.path.join(tf_in, "c_t1_only.vti"), [("ch2", t1)])

fit_source = simple.OpenDataFile(fit_vti)
_, fitted = mce.reduce_multichannel(fit_source, "PCA", "6D", ReferenceSampleSize=2000)
fitted.UpdatePipeline()
coords = vtk_to_numpy(simple.servermanager.Fetch(fitted).GetPointData().GetArray(
    "ReducedCoordinates"))
size = float((coords.max(axis=0) - coords.min(axis=0)).max())
widgets = []
for q, colour in ((0.3, (1, 0, 0)), (0.6, (0, 1, 0)), (0.85, (0, 0.4, 1))):
    widgets += [float(v) for v in np.quantile(coords, q, axis=0)] + [0.08 * size] + \
        list(colour) + [0.8]
display = mce.show_gaussian_tf(fitted, simple.CreateView("RenderView"), widgets=widgets)
tf_file = mce.save_transfer_function(display, os.path.join(work, "brain.mcvtf"))


def run_tool(*extra):
    result = subprocess.run([PVBATCH, SCRIPT, "--input", tf_in, "--output", tf_out,
                             "--size", "300", "300"] + list(extra),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, timeout=1800)
    print(result.stdout[-2500:])
    try:
        with open(os.path.join(tf_out, "index.json")) as f:
            volumes = {r["name"]: r for r in json.load(f)["volumes"]}
    except (OSError, ValueError):
        volumes = {}
    return result, volumes


run, tf_records = run_tool("--transfer-function", tf_file)
checker.check(run.returncode == 0 and sorted(tf_records) == ["a_fit.vti", "b_changed.vti",
                                                             "c_t1_only.vti"],
              "--transfer-function: exit code %d, volumes %s" % (run.returncode,
                                                                 sorted(tf_records)))
fit_r, changed_r, t1_r = (tf_records.get(n, {}) for n in ("a_fit.vti", "b_changed.vti",
                                                         "c_t1_only.vti"))
for name, r in (("a_fit.vti", fit_r), ("b_changed.vti", changed_r)):
    checker.check(r.get("status") == "ok" and r.get("representation") == "Gaussian TF Volume"
                  and (r.get("transfer_function") or {}).get("file") == tf_file and
                  r.get("voxels") == t1.size,
                  "--transfer-function: %s drawn as a Gaussian TF Volume with %s (%s)"
                  % (name, os.path.basename(tf_file), r.get("error", r.get("representation"))))
checker.check(fit_r.get("out_of_model_voxels") == 0 and fit_r.get("out_of_model_share") == 0.0,
              "--transfer-function: no voxel of the fit volume is out of the model (%s)"
              % fit_r.get("out_of_model_voxels"))
share = changed_r.get("out_of_model_share", 0)
checker.check(changed_r.get("out_of_model_voxels", 0) > 0 and
              abs(share - changed_r["out_of_model_voxels"] / float(t1.size)) < 1e-12,
              "--transfer-function: the changed volume has %s voxels out of the model "
              "(share %.4f%%)" % (changed_r.get("out_of_model_voxels"), 100 * share))
checker.check(t1_r.get("status") == "error" and "no channel 'aal'" in t1_r.get("error", ""),
              "--transfer-function: the volume without aal is an error entry naming it: %s"
              % t1_r.get("error"))
tf_html = open(os.path.join(tf_out, "index.html")).read()
caption = "%.2f%% of the voxels (%d of %d)" % (100 * share, changed_r.get("out_of_model_voxels", 0),
                                               t1.size)
checker.check("out of model" in tf_html and caption in tf_html and "brain.mcvtf" in tf_html,
              "--transfer-function: the index captions give the out-of-model share (%s)" % caption)
for name, r in (("a_fit.vti", fit_r), ("b_changed.vti", changed_r)):
    if r.get("status") == "ok":
        means, n, dominant = hue_means(r, tf_out)
        checker.check(n > 500, "--transfer-function: %s thumbnail shows the widgets' colours "
                      "(%d bright pixels, dominated by R, G, B: %s)" % (name, n, list(dominant)))

again, again_records = run_tool("--transfer-function", tf_file)
checker.check(again.returncode == 0 and "0 processed, 3 skipped" in again.stdout,
              "--transfer-function: a second run reuses both snapshots (and the failed one)")
plain, plain_records = run_tool()
checker.check(plain.returncode == 0 and "3 processed" in plain.stdout and
              plain_records.get("a_fit.vti", {}).get("transfer_function") is None and
              "representation" not in plain_records.get("a_fit.vti", {}),
              "a run without --transfer-function redoes the snapshots made with one")
bad_tf = os.path.join(work, "bad.mcvtf")
with open(bad_tf, "w") as f:
    f.write(open(tf_file).read()[:100])
bad, _ = run_tool("--transfer-function", bad_tf)
checker.check(bad.returncode == 1 and bad_tf in bad.stdout and "not valid JSON" in bad.stdout
              and "processed" not in bad.stdout,
              "a truncated transfer-function file stops the run before any volume (exit %d)"
              % bad.returncode)
checker.finish()
