"""Transfer-function files (``.mcvtf``): the Gaussian widgets of a "Gaussian TF Volume"
display kept in a file, together with the reduction model whose coordinates they live in,
so that the same widgets give the same colours to the same tissue in every volume.

A widget's centre is a point of the reduced domain; a domain fitted on another volume is
another domain, where that point means other tissue. The file therefore names the model
(a ``.mcvmodel``, see models.py) and its checksum, and loading or applying it switches the
reduction to that model before the widgets are set.

The file is JSON (UTF-8)::

    {
      "format": "multichannel-explorer-transfer-function",
      "version": 1,
      "coordinates": "ReducedCoordinates",          # the display's coordinate array
      "channels": ["ch2", "aal"],                     # the channels the model reads
      "model": {"file": "brain.mcvmodel",             # relative to this file when possible
                "crc32": 1234567890, "method": "PCA", "channels": ["ch2", "aal"]},
      "widgets": [{"centre": [cx, cy, cz], "sigma": s, "colour": [r, g, b],
                   "opacity": a, "hidden": false, "name": "ch2 mid"}, ...]
    }

A hidden widget (the editor's eye button) has ``"hidden": true`` and its peak opacity in
``"opacity"``: the display holds 0 for it in GaussianWidgets and the opacity in
GaussianWidgetsHidden, and gets both back on loading. ``"name"`` (optional, only for a
widget that has one) is its GaussianWidgetNames entry, the legend's and the editor's name.
"""

import json
import math
import os

from ._common import _display_view, _simple, _view_time
from .models import _reduction_of, read_model, save_model
from .transfer_function import (WIDGET_FIELDS, _coordinates_name, _gaussian_display,
                                _set_widget_state, check_widget_values, show_gaussian_tf)

__all__ = [
    "TRANSFER_FUNCTION_FORMAT",
    "TRANSFER_FUNCTION_VERSION",
    "apply_transfer_function",
    "load_transfer_function",
    "read_transfer_function",
    "save_transfer_function",
    "transfer_function_text",
]

TRANSFER_FUNCTION_FORMAT = "multichannel-explorer-transfer-function"
TRANSFER_FUNCTION_VERSION = 1
_EXTENSION = ".mcvtf"


def _hidden_list(display):
    """GaussianWidgetsHidden as floats, or [] when it does not match the widget count (the
    editor then ignores it too)."""
    prop = display.GetProperty("GaussianWidgetsHidden")
    hidden = [float(v) for v in prop] if prop is not None else []
    count = len(display.GetProperty("GaussianWidgets")) // len(WIDGET_FIELDS)
    return hidden if len(hidden) == count else []


def _write_file(path, text):
    """Writes `text` under a temporary name beside `path`, then renames it into place, so
    that no half-written file is ever left under the name."""
    tmp = "%s.tmp-%d" % (path, os.getpid())
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise ValueError("The transfer function %s cannot be written (%s)."
                         % (path, e.strerror or e))


def transfer_function_text(display, model_path, tf_path):
    """The JSON text of a transfer-function file at `tf_path` for the widgets of `display`,
    whose coordinates come from the model file `model_path` (which must exist)."""
    header = read_model(model_path)
    widgets = [float(v) for v in display.GetProperty("GaussianWidgets")]
    check_widget_values(widgets, "GaussianWidgets of the display")
    hidden = _hidden_list(display)
    names = [str(v) for v in display.GetProperty("GaussianWidgetNames")]
    entries = []
    n = len(WIDGET_FIELDS)
    for i in range(len(widgets) // n):
        w = widgets[i * n:(i + 1) * n]
        is_hidden = bool(hidden) and hidden[i] >= 0
        entry = {"centre": w[0:3], "sigma": w[3], "colour": w[4:7],
                 "opacity": hidden[i] if is_hidden else w[7], "hidden": is_hidden}
        if i < len(names) and names[i]:
            # the legend's and the panel's name ("ch2 mid", an atlas region): a volume the
            # file is applied to shows the same names beside the same colours
            entry["name"] = names[i]
        entries.append(entry)
    folder = os.path.dirname(os.path.abspath(tf_path))
    try:
        reference = os.path.relpath(os.path.abspath(model_path), folder)
    except ValueError:  # another drive (Windows): no relative path exists
        reference = os.path.abspath(model_path)
    channels = list(header["features"]["channels"])
    content = {
        "format": TRANSFER_FUNCTION_FORMAT,
        "version": TRANSFER_FUNCTION_VERSION,
        "coordinates": _coordinates_name(display),
        "channels": channels,
        "model": {"file": reference, "crc32": int(header["crc32"]),
                  "method": header["reduction"]["method"], "channels": channels},
        "widgets": entries,
    }
    # json writes a float as its shortest repr: read back, it is the same double.
    return json.dumps(content, indent=2, allow_nan=False) + "\n"


def save_transfer_function(display, path):
    """Saves the Gaussian widgets of `display` (a "Gaussian TF Volume" representation) to
    the transfer-function file `path` (``.mcvtf``) and returns its absolute path.

    The file refers to the reduction model the widgets live in: the ModelFile of the
    DimensionReduction upstream of the display when it has one, else the model that
    reduction fitted, saved beside the file as ``<stem>.mcvmodel`` (save_model). Load it
    on another display with load_transfer_function, or apply it to other volumes with
    apply_transfer_function: the same tissue gets the same colours::

        _, red = mce.reduce_multichannel(volume, "PCA", "6D")
        display = mce.show_gaussian_tf(red, widgets=[(0.2, 0.1, 0, 0.05, 1, 0, 0, 1)])
        mce.save_transfer_function(display, "brain.mcvtf")   # + brain.mcvmodel
        mce.apply_transfer_function(other_volume, "brain.mcvtf")
    """
    display = _gaussian_display(display, "save_transfer_function")
    path = os.path.abspath(str(path))
    if not path.endswith(_EXTENSION):
        raise ValueError("A transfer-function file ends in %s (got %s)." % (_EXTENSION, path))
    if not os.path.isdir(os.path.dirname(path)):
        raise ValueError("The transfer function %s cannot be written: its folder does not "
                         "exist." % path)
    reduction = _reduction_of(display)
    model = str(reduction.ModelFile or "")
    if model:
        model = os.path.abspath(model)
    else:
        # the fit of the time step the display's view shows
        model = save_model(reduction, path[:-len(_EXTENSION)] + ".mcvmodel",
                           _display_view(display))
    _write_file(path, transfer_function_text(display, model, path))
    return path


def _number(value, where):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError("%s is %r, not a number" % (where, value))
    return float(value)


def _numbers(value, count, where):
    if not isinstance(value, list) or len(value) != count:
        raise ValueError("%s is %r, not a list of %d numbers" % (where, value, count))
    return [_number(v, "%s[%d]" % (where, i)) for i, v in enumerate(value)]


class TransferFunctionFile(object):
    """A transfer-function file, read and checked (read_transfer_function):

    ``path``, ``model`` (absolute path of its model, which exists and has the checksum the
    file names), ``model_header`` (read_model's dict), ``coordinates``, ``channels``,
    ``widgets`` (the flat GaussianWidgets list, 0 opacity for hidden widgets),
    ``hidden`` (the GaussianWidgetsHidden list, [] when no widget is hidden) and ``names``
    (the GaussianWidgetNames list, "" for a widget without one; [] when none has one)."""

    def __init__(self, path, model, model_header, coordinates, channels, widgets, hidden,
                 names=None):
        self.path = path
        self.model = model
        self.model_header = model_header
        self.coordinates = coordinates
        self.channels = channels
        self.widgets = widgets
        self.hidden = hidden
        self.names = names or []


def read_transfer_function(path):
    """Reads and checks the transfer-function file `path`; returns a TransferFunctionFile.
    Raises ValueError naming the file when it cannot be read, is not JSON (truncated), is
    no transfer-function file or one of a newer version, holds a widget value that is not
    a finite number, or when its model is missing or is not the file it was saved with
    (another checksum)."""
    path = os.path.abspath(str(path))
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise ValueError("The transfer function %s cannot be read (%s)."
                         % (path, e.strerror or e))

    try:
        # NaN and Infinity (which Python's json reads) come back as floats, and the widget
        # check names the widget and the field that holds one.
        content = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as e:
        raise ValueError("%s is not a transfer-function file, or it is truncated: it is not "
                         "valid JSON (%s)." % (path, e))
    if not isinstance(content, dict) or content.get("format") != TRANSFER_FUNCTION_FORMAT:
        raise ValueError("%s is not a transfer-function file (no \"format\": \"%s\")."
                         % (path, TRANSFER_FUNCTION_FORMAT))
    version = content.get("version")
    if not isinstance(version, int) or isinstance(version, bool) or version < 1:
        raise ValueError("The transfer function %s has no valid format version (%r)."
                         % (path, version))
    if version > TRANSFER_FUNCTION_VERSION:
        raise ValueError("The transfer function %s has format version %d; this plugin reads "
                         "version %d." % (path, version, TRANSFER_FUNCTION_VERSION))
    try:
        coordinates = content.get("coordinates", "ReducedCoordinates")
        if not isinstance(coordinates, str) or not coordinates:
            raise ValueError("\"coordinates\" is %r, not an array name" % (coordinates,))
        channels = content.get("channels")
        if not isinstance(channels, list) or not all(isinstance(c, str) for c in channels):
            raise ValueError("\"channels\" is %r, not a list of names" % (channels,))
        model = content.get("model")
        if not isinstance(model, dict) or not isinstance(model.get("file"), str) or \
                not model["file"]:
            raise ValueError("it names no model file (\"model\": {\"file\": ...})")
        crc = model.get("crc32")
        if not isinstance(crc, int) or isinstance(crc, bool):
            raise ValueError("its model has no crc32 (%r)" % (crc,))
        entries = content.get("widgets")
        if not isinstance(entries, list):
            raise ValueError("\"widgets\" is %r, not a list" % (entries,))
        widgets, hidden, names = [], [], []
        for i, w in enumerate(entries):
            where = "widget %d" % i
            if not isinstance(w, dict):
                raise ValueError("%s is %r, not an object" % (where, w))
            centre = _numbers(w.get("centre"), 3, where + "'s centre")
            sigma = _number(w.get("sigma"), where + "'s sigma")
            colour = _numbers(w.get("colour"), 3, where + "'s colour")
            opacity = _number(w.get("opacity"), where + "'s opacity")
            is_hidden = w.get("hidden", False)
            if not isinstance(is_hidden, bool):
                raise ValueError("%s's hidden is %r, not true or false" % (where, is_hidden))
            name = w.get("name", "")  # optional: files saved before names were kept
            if not isinstance(name, str):
                raise ValueError("%s's name is %r, not text" % (where, name))
            names.append(name)
            widgets.extend(centre + [sigma] + colour + [0.0 if is_hidden else opacity])
            hidden.append(opacity if is_hidden else -1.0)
        check_widget_values(widgets, "widgets")
        for i, value in enumerate(hidden):
            if not math.isfinite(value):
                raise ValueError("widget %d's opacity is %r, not a finite number" % (i, value))
    except ValueError as e:
        raise ValueError("The transfer function %s is not valid: %s." % (path, e))
    if not any(h >= 0 for h in hidden):
        hidden = []
    if not any(names):
        names = []
    model_path = model["file"]
    if not os.path.isabs(model_path):
        model_path = os.path.join(os.path.dirname(path), model_path)
    model_path = os.path.normpath(model_path)
    if not os.path.exists(model_path):
        raise ValueError("%s is a transfer-function file without its model: the reduction "
                         "model %s does not exist (keep the .mcvmodel beside the .mcvtf it "
                         "was saved with)." % (path, model_path))
    header = read_model(model_path)
    if int(header["crc32"]) != crc:
        raise ValueError("The transfer function %s was saved with another reduction model: "
                         "%s has checksum %08x, the transfer function expects %08x (the "
                         "model was refitted or replaced; the widgets would colour other "
                         "tissue)." % (path, model_path, int(header["crc32"]), crc))
    return TransferFunctionFile(path, model_path, header, coordinates, channels, widgets,
                                hidden, names)


def _set_widgets(display, tf):
    """The file's widgets, which are hidden and their names (none: the display's names
    are cleared, they named other widgets) in one property update."""
    display.CoordinateArray = tf.coordinates
    _set_widget_state(display, tf.widgets, tf.hidden, tf.names)


def load_transfer_function(display, path):
    """Loads the transfer-function file `path` onto `display` (a "Gaussian TF Volume"
    representation): sets the ModelFile of the DimensionReduction upstream of the display
    to the file's model (so the coordinates are the model's, those the widgets were placed
    in), then the widgets, hidden ones included, their names and the coordinate array.
    The file and its model are checked first (read_transfer_function): on any error
    (ValueError naming the file) nothing is changed. Returns the TransferFunctionFile
    read."""
    display = _gaussian_display(display, "load_transfer_function")
    tf = read_transfer_function(path)
    reduction = _reduction_of(display)
    current = str(reduction.ModelFile or "")
    if not current or os.path.abspath(current) != tf.model:
        reduction.ModelFile = tf.model
        time = _view_time(_display_view(display))
        said = _run_reduction(reduction, tf.coordinates, time)
        if said is not None:
            # The volume cannot take this model (a channel is missing): back to what it
            # was, widgets untouched.
            reduction.ModelFile = current
            reduction.UpdatePipeline(time)
            raise ValueError("The transfer function %s cannot be loaded onto this display: "
                             "%s" % (tf.path, said))
    _set_widgets(display, tf)
    return tf


class _ErrorCatcher(object):
    """The error messages a VTK object reports while it is observed (builtin sessions,
    where the filter runs in this process)."""

    def __init__(self, obj):
        from vtkmodules.util.misc import calldata_type
        from vtkmodules.util.vtkConstants import VTK_STRING

        self.messages = []
        self.object = obj

        @calldata_type(VTK_STRING)
        def on_error(caller, event, text):
            self.messages.append(str(text))

        self._callback = on_error
        self.tag = obj.AddObserver("ErrorEvent", on_error) if obj is not None else None

    def stop(self):
        if self.tag is not None:
            self.object.RemoveObserver(self.tag)
            self.tag = None

    def text(self):
        """The last message without VTK's "ERROR: In file, line N / vtkClass (0x...): "."""
        if not self.messages:
            return None
        text = self.messages[-1].strip()
        marker = text.find("): ")
        return text[marker + 3:].strip() if marker >= 0 else text


def _run_reduction(reduction, coordinates, time):
    """Updates `reduction` at `time` (the step on screen: the view then draws what was
    computed); None when its output has the array `coordinates`, else what went wrong
    (the reduction's own error message when this process runs it)."""
    catcher = _ErrorCatcher(reduction.GetClientSideObject())
    try:
        reduction.UpdatePipeline(time)
    finally:
        catcher.stop()
    info = reduction.GetDataInformation().DataInformation.GetPointDataInformation()
    if info.GetArrayInformation(coordinates) is not None:
        return None
    return catcher.text() or ("the reduction with the model %s failed (see the messages "
                              "above)" % reduction.ModelFile)


def apply_transfer_function(volume, path, view=None, **props):
    """Applies the transfer-function file `path` to the multichannel `volume`: a
    ``reduce_multichannel(volume, model=<the file's model>)`` (no fit: the model's
    coordinates) shown as a "Gaussian TF Volume" in `view` (default: the active render
    view) with the file's widgets. Returns ``(reduction, display)``; the same tissue gets
    the same colours in every volume the file is applied to, and voxels unlike anything in
    the model are counted in its NumberOfOutOfModelVoxels.

    ``props`` are further DimensionReduction properties (Device). Raises ValueError, with
    nothing left in the pipeline, when the file or its model is bad
    (read_transfer_function) or when the reduction fails, e.g. when the volume lacks a
    channel the model was fitted with (the message names the channel)::

        reduction, display = mce.apply_transfer_function(next_volume, "brain.mcvtf")
        reduction.UpdatePropertyInformation()
        print(reduction.GetPropertyValue("NumberOfOutOfModelVoxels"))
    """
    from .reduction import reduce_multichannel

    simple = _simple()
    tf = read_transfer_function(path)
    reduction, _ = reduce_multichannel(volume, model=tf.model, **props)
    said = _run_reduction(reduction, tf.coordinates, _view_time(view))  # the step on screen
    if said is not None:
        simple.Delete(reduction)
        raise ValueError("The transfer function %s cannot be applied to %s: %s"
                         % (tf.path, _source_name(volume), said))
    reduction.UpdatePropertyInformation()
    try:
        display = show_gaussian_tf(reduction, view, coordinates=tf.coordinates)
        _set_widgets(display, tf)
    except Exception:
        simple.Delete(reduction)
        raise
    return reduction, display


def _source_name(proxy):
    """The volume's file when its reader has one, else its pipeline name."""
    files = proxy.GetProperty("FileName") or proxy.GetProperty("FileNames")
    if files is not None:
        values = [str(v) for v in files] if not isinstance(files, str) else [files]
        values = [v for v in values if v]
        if values:
            return values[0] if len(values) == 1 else "%s (+%d files)" % (values[0],
                                                                          len(values) - 1)
    simple = _simple()
    for (name, _), p in simple.GetSources().items():
        if p is proxy or getattr(p, "SMProxy", None) is getattr(proxy, "SMProxy", proxy):
            return name
    return "the volume"
