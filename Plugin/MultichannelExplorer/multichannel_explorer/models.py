"""Reduction models: what a DimensionReduction fitted, saved as a `.mcvmodel` file and
applied to other volumes and time steps (DimensionReduction's ModelFile), so that the same
tissue gets the same reduced coordinates, hence the same colours, everywhere.

The file (written by the plugin's ReductionModelWriter; Filters/Reduction/
mcvReductionModelFile.h documents it): the magic ``MCVMODEL``, a uint32 format version, a
uint32 header length, a JSON header, binary blocks, and a CRC-32 of everything before it.
"""

import json
import os
import struct
import zlib

from ._common import _filter, _is_representation, _simple, _view_time

__all__ = [
    "MODEL_FORMAT_VERSION",
    "read_model",
    "save_model",
]

MODEL_FORMAT_VERSION = 1
_MAGIC = b"MCVMODEL"


def read_model(path):
    """The JSON header of the reduction model file `path` as a dict (channels, features,
    reduction, fit, blocks), plus ``"version"`` and ``"crc32"`` (the file's checksum).
    Raises ValueError naming the file when it is not a complete model of a version this
    plugin reads (missing, truncated, damaged, another format, a newer version)::

        info = mce.read_model("brain.mcvmodel")
        print(info["features"]["channels"], info["reduction"]["method"])
    """
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise ValueError("The reduction model %s cannot be read (%s)." % (path, e.strerror))
    if data[:8] != _MAGIC:
        raise ValueError("%s is not a reduction model file (it does not start with MCVMODEL)."
                         % path)
    if len(data) < 20:
        raise ValueError("The reduction model %s is truncated (%d bytes)." % (path, len(data)))
    version, header_size = struct.unpack("<II", data[8:16])
    if version == 0 or version > MODEL_FORMAT_VERSION:
        raise ValueError("The reduction model %s has format version %d; this plugin reads "
                         "version %d." % (path, version, MODEL_FORMAT_VERSION))
    crc = struct.unpack("<I", data[-4:])[0]
    if zlib.crc32(data[:-4]) & 0xFFFFFFFF != crc:
        raise ValueError("The reduction model %s is damaged or truncated: its checksum does "
                         "not match its %d bytes." % (path, len(data)))
    if 16 + header_size + 4 > len(data):
        raise ValueError("The reduction model %s is truncated." % path)
    try:
        header = json.loads(data[16:16 + header_size].decode("utf-8"))
    except ValueError as e:
        raise ValueError("The reduction model %s has a header that is not JSON (%s)." % (path, e))
    header["version"] = version
    header["crc32"] = crc
    return header


def _reduction_of(target):
    """The DimensionReduction of `target`: itself, or the nearest one upstream of a source
    or a display (first inputs first)."""
    if _is_representation(target):
        target = target.Input
    pending = [target]
    while pending:
        proxy = pending.pop(0)
        if proxy is None:
            continue
        if proxy.GetXMLName() == "DimensionReduction":
            return proxy
        inputs = proxy.GetProperty("Input") is not None and proxy.Input
        pending.extend(inputs if isinstance(inputs, (list, tuple)) else [inputs] if inputs else [])
    raise ValueError("%r is not a DimensionReduction and has none upstream." % (target,))


def save_model(reduction, path, view=None):
    """Writes the reduction model that `reduction` (a DimensionReduction, or a source or
    display downstream of one) fitted to `path` (`.mcvmodel`; written by the server, like
    every ParaView writer). Updates the reduction first, at the time step `view` shows
    (default: the active view's; with FitTime "Each time step" each step has its own
    fit). Returns the absolute path.

    Apply it to other volumes with ``reduce_multichannel(volume, model=path)`` or
    DimensionReduction's ModelFile: no new fit, the channels matched by name, the same
    normalisation, the same reduced domain. The model needs the features computed by the
    reduction from the channels (its default); a reduction of an input Features array has
    none (ValueError)::

        feats, red = mce.reduce_multichannel(volume, "PCA", "6D")
        mce.save_model(red, "brain.mcvmodel")
        _, other = mce.reduce_multichannel(next_volume, model="brain.mcvmodel")
    """
    simple = _simple()
    reduction = _reduction_of(reduction)
    path = os.path.abspath(str(path))
    if not path.endswith(".mcvmodel"):
        raise ValueError("A reduction model file ends in .mcvmodel (got %s)." % path)
    # With FitTime "Each time step" every step has its own fit: the one on screen. Updated
    # without a time, the reduction (and a new writer) would keep the step it last ran.
    time = _view_time(view)
    reduction.UpdatePipeline(time)
    spectrum = reduction.GetDataInformation(1).DataInformation
    if spectrum.GetFieldDataInformation().GetArrayInformation("ReductionModel") is None:
        raise ValueError("This DimensionReduction has no model to save: it failed, or it "
                         "reduces an input feature array, whose normalisation is not known "
                         "here. Let DimensionReduction compute the features from the channels "
                         "(FeatureSet 6D, 24D or Custom).")
    from paraview import servermanager

    remote = servermanager.ActiveConnection is not None and \
        servermanager.ActiveConnection.IsRemote()
    before = None if remote or not os.path.exists(path) else os.stat(path).st_mtime_ns
    # The writer is connected to the Spectrum port directly: a Python proxy of that port
    # (simple.OutputPort, SaveData) touches the reduction and makes it fit again.
    made = servermanager.ProxyManager().NewProxy("writers", "ReductionModelWriter")
    if made is None:
        raise RuntimeError("No reduction model writer: is the MultichannelExplorer plugin "
                           "loaded on the server too?")
    writer = servermanager._getPyProxy(made)
    writer.SMProxy.GetProperty("Input").SetInputConnection(0, reduction.SMProxy, 1)
    writer.FileName = path
    writer.UpdatePipeline(time)
    del writer
    if not remote:
        # The writer reports its errors to the log only: the file itself says whether it
        # was written.
        if not os.path.exists(path) or (before is not None and
                                        os.stat(path).st_mtime_ns == before):
            raise RuntimeError("The reduction model %s was not written (see the messages "
                               "above)." % path)
        read_model(path)
    return path


def _model_reduction(source, path, props):
    """A DimensionReduction(Input=source) applying the model file `path`."""
    reduction = _filter("DimensionReduction")(Input=source)
    reduction.ModelFile = os.path.abspath(str(path))
    for name, value in props.items():
        setattr(reduction, name, value)
    return reduction
