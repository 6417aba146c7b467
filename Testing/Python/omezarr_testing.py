"""OME-Zarr images written for the tests with Debian's python3-zarr (Zarr format 2) from the
real 3-channel brain (Colin27 T1 ch2 + the AAL and Brodmann atlases, 181 x 217 x 181 uint8).

The NGFF 0.4 metadata (multiscales with its axes, datasets and coordinateTransformations;
omero channels) is written by hand with zarr's API, as the specification describes it, so
that the tests know every value the reader must give back.
"""
import os
import shutil

import numpy as np
import zarr
from numcodecs import Blosc, GZip, Zlib

import mcv_testing as T

NAMES = ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")
LABELS = ["T1 (ch2)", "AAL", "Brodmann"]
COLORS = ["FFFFFF", "FF0000", "00FF00"]


def brain_arrays(names=NAMES):
    """The channels as numpy arrays in NGFF order (c, z, y, x), read with the plugin's NIfTI
    reader and fetched to the client."""
    return T.brain_arrays([n[:-len(".nii.gz")] for n in names])


def compressor_of(name):
    return {"blosc": Blosc(cname="lz4", clevel=5, shuffle=Blosc.SHUFFLE),
            "zlib": Zlib(level=6), "gzip": GZip(level=6), "none": None}[name]


def write_image(folder, levels, axes="czyx", scales=None, translations=None,
                chunks=None, compressor="blosc", separator=".", order="C", dtype=None,
                fill_value=0, labels=LABELS, colors=COLORS, unit="micrometer",
                time_unit="second", multiscale_scale=None):
    """Writes an OME-Zarr image: `levels` is a list of numpy arrays (finest first) in the
    order of `axes`; `scales`/`translations` one list per level (per axis). Returns the
    folder."""
    if os.path.exists(folder):
        shutil.rmtree(folder)
    store = zarr.DirectoryStore(folder, dimension_separator=separator)
    root = zarr.group(store=store, overwrite=True)
    datasets = []
    for i, data in enumerate(levels):
        if dtype is not None:
            data = data.astype(dtype)
        chunk_shape = chunks[i] if isinstance(chunks, list) else (chunks or data.shape)
        root.create_dataset(str(i), data=data, chunks=chunk_shape,
                            compressor=compressor_of(compressor), order=order,
                            fill_value=fill_value, dimension_separator=separator,
                            dtype=data.dtype, overwrite=True)
        transforms = [{"type": "scale", "scale": list(map(float, scales[i]))}]
        if translations is not None:
            transforms.append({"type": "translation",
                               "translation": list(map(float, translations[i]))})
        datasets.append({"path": str(i), "coordinateTransformations": transforms})
    axis_types = {"t": "time", "c": "channel", "z": "space", "y": "space", "x": "space"}
    axis_list = []
    for a in axes:
        entry = {"name": a, "type": axis_types[a]}
        if axis_types[a] == "space" and unit:
            entry["unit"] = unit
        if a == "t" and time_unit:
            entry["unit"] = time_unit
        axis_list.append(entry)
    multiscale = {"version": "0.4", "name": "brain", "axes": axis_list, "datasets": datasets}
    if multiscale_scale is not None:
        multiscale["coordinateTransformations"] = [
            {"type": "scale", "scale": list(map(float, multiscale_scale))}]
    root.attrs["multiscales"] = [multiscale]
    if labels is not None:
        root.attrs["omero"] = {"version": "0.4", "channels": [
            {"label": l, "color": c, "active": True,
             "window": {"start": 0, "end": 255, "min": 0, "max": 255}}
            for l, c in zip(labels, colors)]}
    return folder


def brain_image(folder, brain, axes="czyx", time_points=1, **kwargs):
    """The brain as a 2-level image: level 0 the channels as they are (voxels of 0.5 x 0.6
    x 0.7 along z, y, x), level 1 every second voxel along z, y, x (exactly the source's
    values there; twice the spacing, the origin moved by half a coarse voxel). With axes
    'tczyx', `time_points` time points, point k holding the brain + 100 k as uint16 (2.5 s
    apart from 10 s). Returns (folder, levels, scales, translations)."""
    levels = [brain, brain[:, ::2, ::2, ::2]]
    scales = [[1.0, 0.5, 0.6, 0.7], [1.0, 1.0, 1.2, 1.4]]
    translations = [[0.0, -10.0, 20.0, 5.5], [0.0, -9.75, 20.3, 5.85]]
    if axes == "tczyx":
        levels = [np.stack([l.astype(np.uint16) + 100 * k for k in range(time_points)])
                  for l in levels]
        scales = [[2.5] + s for s in scales]
        translations = [[10.0] + t for t in translations]
    write_image(folder, levels, axes=axes, scales=scales, translations=translations, **kwargs)
    return folder, levels, scales, translations
