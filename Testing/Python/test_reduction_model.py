"""Reduction models: one fit, saved as a .mcvmodel file and applied to other volumes
(DimensionReduction's ModelFile, multichannel_explorer.save_model / reduce_multichannel
with model=), on the real brain (Colin27 T1 + AAL atlas, every 3rd voxel).

Known answers:
- applied to its own fit volume, a model gives the fit's coordinates bit for bit, and no
  voxel lies outside it; with the channels in another order, the same;
- on a volume whose upper half changed (T1 x 1.3), every voxel more than 2 slices from the
  change keeps its coordinates exactly, while the changed half moves (a refit moves the
  unchanged half too: shown, not required);
- a region no reference resembles (T1 x 6 in a cube) is outside the model (ModelDistance >
  1.5) and counted, the rest of the volume is not;
- a missing channel is an error naming it; another spacing a warning naming both;
- bad files (missing, truncated, damaged, a future version, sizes that disagree, NaN): a
  clear error, nothing drawn (no ReducedCoordinates); read_model says the same in Python.
PCA, Isomap, LLE and UMAP each.
"""

import json
import os
import struct
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
import numpy as np  # noqa: E402
from paraview import servermanager  # noqa: E402
from paraview.simple import Delete, OpenDataFile  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from multichannel_explorer._common import _filter  # noqa: E402

C = T.Checker("test_reduction_model")
OUT = os.path.join(T.output_dir(), "reduction_model")
os.makedirs(OUT, exist_ok=True)
SAMPLE = 2000


def write_vti(name, channels, spacing=(3.0, 3.0, 3.0)):
    return T.write_vti(os.path.join(OUT, name), channels, spacing)


def coordinates(proxy):
    data = servermanager.Fetch(proxy)
    array = data.GetPointData().GetArray("ReducedCoordinates")
    return None if array is None else vtk_to_numpy(array).copy(), data


def distances(data):
    array = data.GetPointData().GetArray("ModelDistance")
    return None if array is None else vtk_to_numpy(array).copy()


def apply(path, model):
    source = OpenDataFile(path)
    _, reduction = mce.reduce_multichannel(source, model=model)
    messages = T.Messages(reduction)
    reduction.UpdatePipeline()
    reduction.UpdatePropertyInformation()
    coords, data = coordinates(reduction)
    return coords, data, messages, (source, reduction)


def drop(proxies):
    for p in reversed(proxies):
        Delete(p)


brain = T.brain_arrays(("ch2", "aal"), step=3).astype(np.float32)
t1, aal = brain[0], brain[1]
nz = t1.shape[0]
fit_path = write_vti("fit.vti", [("ch2", t1), ("aal", aal)])
swapped_path = write_vti("swapped.vti", [("aal", aal), ("ch2", t1)])
half = t1.copy()
half[nz // 2:] *= 1.3
half_path = write_vti("half.vti", [("ch2", half), ("aal", aal)])
cube = t1.copy()
cz, cy, cx = (s // 2 for s in t1.shape)
cube[cz - 3:cz + 3, cy - 3:cy + 3, cx - 3:cx + 3] = 6.0 * t1.max()
cube_path = write_vti("cube.vti", [("ch2", cube), ("aal", aal)])
one_channel_path = write_vti("only_t1.vti", [("ch2", t1)])
spacing_path = write_vti("spacing.vti", [("ch2", t1), ("aal", aal)], spacing=(2.0, 3.0, 3.0))

models = {}
for method in ("PCA", "Isomap", "LLE", "UMAP"):
    source = OpenDataFile(fit_path)
    _, fitted = mce.reduce_multichannel(source, method, "6D", ReferenceSampleSize=SAMPLE)
    fitted.UpdatePipeline()
    fit_coords, _ = coordinates(fitted)
    model = mce.save_model(fitted, os.path.join(OUT, method + ".mcvmodel"))
    models[method] = model
    after, _ = coordinates(fitted)
    C.check(np.array_equal(after, fit_coords), "%s: saving the model does not refit" % method)
    header = mce.read_model(model)
    C.check(sorted(header["features"]["channels"]) == ["aal", "ch2"] and
            header["reduction"]["method"] == method and
            header["reduction"]["references"] <= SAMPLE and
            len(header["features"]["offset"]) == 4,
            "%s: the file names the channels, method, references and 4 offsets (%s, %d refs)"
            % (method, header["features"]["channels"], header["reduction"]["references"]))

    same, data, messages, proxies = apply(fit_path, model)
    d = distances(data)
    C.check(same is not None and np.array_equal(same, fit_coords),
            "%s: applied to its fit volume, the model gives the fit's coordinates bit for bit"
            % method)
    C.check(d is not None and int((d > 1.5).sum()) == 0 and
            proxies[1].GetProperty("NumberOfOutOfModelVoxels").GetElement(0) == 0,
            "%s: no voxel of the fit volume is outside its model (max ModelDistance %.3f)"
            % (method, -1 if d is None else d.max()))
    drop(proxies)

    swapped, _, _, proxies = apply(swapped_path, model)
    C.check(swapped is not None and np.array_equal(swapped, fit_coords),
            "%s: channels in another order give the same coordinates" % method)
    drop(proxies)

    changed, _, _, proxies = apply(half_path, model)
    far = (nz // 2) - 3  # slices 0 .. far-1 lie more than 2 slices from the change
    plane = t1.shape[1] * t1.shape[2]
    kept = changed is not None and np.array_equal(changed[:far * plane], fit_coords[:far * plane])
    moved = 0.0 if changed is None else float(
        np.mean(np.any(changed[(nz // 2) * plane:] != fit_coords[(nz // 2) * plane:], axis=1)))
    C.check(kept, "%s: with one model, voxels > 2 slices from the changed half keep their "
                  "coordinates exactly" % method)
    C.check(moved > 0.3, "%s: the changed half moves (%.0f%% of its voxels)" % (method, 100 * moved))
    drop(proxies)

    if method in ("PCA", "Isomap"):
        refit_source = OpenDataFile(half_path)
        _, refit = mce.reduce_multichannel(refit_source, method, "6D", ReferenceSampleSize=SAMPLE)
        refit.UpdatePipeline()
        refit_coords, _ = coordinates(refit)
        shift = np.abs(refit_coords[:far * plane] - fit_coords[:far * plane]).max()
        print("     %s: a refit on the changed volume moves unchanged voxels by up to %.3f" % (method, shift))
        drop([refit_source, refit])
    Delete(fitted)
    Delete(source)

# Out of the model: a cube six times brighter than anything in the fit volume.
outside, data, messages, proxies = apply(cube_path, models["PCA"])
d = distances(data)
inside_cube = np.zeros(t1.shape, dtype=bool)
inside_cube[cz - 2:cz + 2, cy - 2:cy + 2, cx - 2:cx + 2] = True
far_from_cube = np.ones(t1.shape, dtype=bool)
far_from_cube[cz - 5:cz + 5, cy - 5:cy + 5, cx - 5:cx + 5] = False
count = proxies[1].GetProperty("NumberOfOutOfModelVoxels").GetElement(0)
C.check(d is not None and bool(np.all(d.reshape(t1.shape)[inside_cube] > 1.5)),
        "out of model: every voxel inside the bright cube has ModelDistance > 1.5 (min %.1f)"
        % (-1 if d is None else d.reshape(t1.shape)[inside_cube].min()))
C.check(d is not None and int((d.reshape(t1.shape)[far_from_cube] > 1.5).sum()) == 0,
        "out of model: no voxel away from the cube is outside the model")
C.check(count == int((d > 1.5).sum()) and count >= 64 and
        T.field_strings(data, "ReductionModelSource") == [models["PCA"]] and
        messages.any_warning("outside the reduction model"),
        "out of model: %d voxels counted, the field data names the model, a warning says so" % count)
drop(proxies)

# A missing channel, another spacing.
missing, data, messages, proxies = apply(one_channel_path, models["PCA"])
C.check(missing is None and messages.any_error("no channel 'aal'", "PCA.mcvmodel"),
        "a missing channel is an error naming it and the model: %s" % messages.errors[-1:])
drop(proxies)
spaced, data, messages, proxies = apply(spacing_path, models["PCA"])
C.check(spaced is not None and messages.any_warning("spacing (2, 3, 3)", "(3, 3, 3"),
        "another spacing is a warning naming both: %s" % messages.warnings[-1:])
drop(proxies)

# Bad model files.
with open(models["PCA"], "rb") as f:
    good = f.read()


def with_crc(body):
    return body + struct.pack("<I", zlib.crc32(body) & 0xFFFFFFFF)


header_size = struct.unpack("<I", good[12:16])[0]
header = json.loads(good[16:16 + header_size].decode())
blocks_start = 16 + header_size


def rewritten(change):
    h = json.loads(json.dumps(header))
    change(h)
    text = json.dumps(h).encode()
    return with_crc(good[:12] + struct.pack("<I", len(text)) + text + good[blocks_start:-4])


nan_body = bytearray(good[:-4])
nan_body[blocks_start:blocks_start + 4] = struct.pack("<f", float("nan"))
bad_files = {
    "missing": (None, "does not exist"),
    "truncated": (good[:len(good) // 2], "checksum"),
    "damaged": (good[:200] + bytes([good[200] ^ 0xFF]) + good[201:], "checksum"),
    "future": (with_crc(good[:8] + struct.pack("<I", 2) + good[12:-4]), "version 2"),
    "other_features": (rewritten(lambda h: h["reduction"].update(featureColumns=6)), "feature columns"),
    "nan": (with_crc(bytes(nan_body)), "non-finite"),
    "not_a_model": (b"P5\n2 2\n255\n" + bytes(4), "not a reduction model"),
}
for name, (content, words) in bad_files.items():
    path = os.path.join(OUT, "bad_%s.mcvmodel" % name)
    if os.path.exists(path):
        os.remove(path)
    if content is not None:
        with open(path, "wb") as f:
            f.write(content)
    try:
        mce.read_model(path)
        python_said = None
    except ValueError as e:
        python_said = str(e)
    source = OpenDataFile(fit_path)
    reduction = _filter("DimensionReduction")(Input=source)
    reduction.ModelFile = path
    messages = T.Messages(reduction)
    reduction.UpdatePipeline()
    coords, _ = coordinates(reduction)
    C.check(coords is None and messages.any_error(words) and messages.any_error(path),
            "bad model (%s): an error naming the file and '%s', nothing drawn: %s"
            % (name, words, messages.errors[-1:]))
    if name not in ("other_features", "nan"):  # read_model checks the header and checksum only
        C.check(python_said is not None and path in python_said,
                "bad model (%s): read_model raises ValueError naming the file: %s"
                % (name, python_said))
    drop([source, reduction])

# No model from a reduction of an input Features array.
source = OpenDataFile(fit_path)
feats, reduction = mce.reduce_multichannel(source, "PCA", "6D", keep_features=True,
                                           ReferenceSampleSize=SAMPLE)
try:
    mce.save_model(reduction, os.path.join(OUT, "features_array.mcvmodel"))
    said = None
except ValueError as e:
    said = str(e)
C.check(said is not None and "normalisation is not known" in said,
        "save_model of a reduction of an input Features array: ValueError (%s)" % said)
C.finish()
