"""Image statistics of rendered views: PNG reading, the 8-bit luminance histogram, its
Shannon entropy and simple statistics (pure VTK + Python, no numpy), and the entropy of a
view's screenshot (used to choose between +v3 and -v3).
"""

import math
import os
import tempfile

from ._common import _simple

__all__ = [
    "image_entropy",
    "image_statistics",
]


def _read_png(path):
    from vtkmodules.vtkIOImage import vtkPNGReader

    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def _luminance_histogram(image):
    """256-bin histogram of the 8-bit luminance of a vtkImageData (RGB, RGBA or grey).
    Pure VTK + Python (ParaView's Python has neither numpy nor vtkImagingStatistics)."""
    from vtkmodules.vtkCommonCore import VTK_UNSIGNED_CHAR
    from vtkmodules.vtkImagingColor import vtkImageLuminance
    from vtkmodules.vtkImagingCore import vtkImageCast, vtkImageExtractComponents

    source = image
    scalars = image.GetPointData().GetScalars()
    if scalars is None:
        raise ValueError("image has no scalars")
    ncomp = scalars.GetNumberOfComponents()
    if ncomp != 1:
        extract = vtkImageExtractComponents()
        extract.SetInputData(image)
        if ncomp >= 3:
            extract.SetComponents(0, 1, 2)
            lum = vtkImageLuminance()
            lum.SetInputConnection(extract.GetOutputPort())
            lum.Update()
            source = lum.GetOutput()
        else:
            extract.SetComponents(0)
            extract.Update()
            source = extract.GetOutput()
    if source.GetPointData().GetScalars().GetDataType() != VTK_UNSIGNED_CHAR:
        cast = vtkImageCast()
        cast.SetInputData(source)
        cast.SetOutputScalarTypeToUnsignedChar()
        cast.ClampOverflowOn()
        cast.Update()
        source = cast.GetOutput()
    data = bytes(memoryview(source.GetPointData().GetScalars()))
    return [data.count(bytes((i,))) for i in range(256)]


def _entropy(counts):
    total = float(sum(counts))
    if total <= 0:
        return 0.0
    return -sum((c / total) * math.log2(c / total) for c in counts if c > 0)


def image_entropy(image_or_path):
    """Shannon entropy (bits) of the 8-bit luminance histogram of an image (a PNG path
    or a vtkImageData)."""
    image = _read_png(image_or_path) if isinstance(image_or_path, str) else image_or_path
    return _entropy(_luminance_histogram(image))


def image_statistics(image_or_path):
    """{'mean', 'stddev', 'entropy', 'non_background_fraction', 'pixels'} of an image's
    8-bit luminance (non-background: pixels that differ from the most common value)."""
    image = _read_png(image_or_path) if isinstance(image_or_path, str) else image_or_path
    counts = _luminance_histogram(image)
    total = float(sum(counts)) or 1.0
    mean = sum(i * c for i, c in enumerate(counts)) / total
    var = sum(c * (i - mean) ** 2 for i, c in enumerate(counts)) / total
    return {
        "mean": mean,
        "stddev": math.sqrt(var),
        "entropy": _entropy(counts),
        "non_background_fraction": 1.0 - max(counts) / total,
        "pixels": int(total),
    }


def _render_entropy(view, resolution=None):
    simple = _simple()
    fd, path = tempfile.mkstemp(prefix="mcv_view_", suffix=".png")
    os.close(fd)
    try:
        params = {}
        if resolution:
            params["ImageResolution"] = list(resolution)
        simple.SaveScreenshot(path, view, **params)
        return image_entropy(path)
    finally:
        try:
            os.remove(path)
        except OSError:
            pass
