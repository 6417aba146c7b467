"""Dimension reduction of a multichannel volume to a 2D/3D domain of reduced coordinates:
DimensionReduction on the channels (the fused path: features computed a slab at a time,
never stored), or MultichannelFeatures followed by DimensionReduction when the features
are wanted as an array.
"""

from ._common import _TracedProperties, _filter

__all__ = [
    "reduce_multichannel",
]

_PRESETS = ("6D", "24D", "Custom")
_PRECISIONS = {"float32": "Float32", "float16": "Float16"}


def reduce_multichannel(source, method="Isomap", features="24D", output_dimension=3,
                        keep_features=False, coordinate_precision="float32", model=None,
                        **props):
    """Feature vectors of a multichannel volume reduced to a 2D/3D domain.

    Returns ``(features_proxy, reduction_proxy)``. ``features`` is a feature set ("6D",
    "24D", "Custom") or the name of a point array of `source` that already holds feature
    vectors (then the reduction reads that array and the first proxy returned is
    `source`). For a feature set:

    * by default (the fused path) one ``DimensionReduction(Input=source,
      FeatureSet=features)`` computes the features from the channels a slab at a time and
      never stores them (memory: the coordinates and one slab, not 4 bytes per feature per
      voxel); it is returned twice, since it also plays the features filter's part (it has
      its FeatureSet, Channels, Normalization, MaskBackground and BackgroundThreshold
      properties);
    * ``keep_features=True`` builds ``MultichannelFeatures(Input=source,
      FeatureSet=features)`` followed by DimensionReduction, as before the fused path: the
      Features array is then in the output (probing shows it). Same coordinates.

    ``coordinate_precision="float16"`` stores ReducedCoordinates as IEEE binary16
    (DimensionReduction's CoordinatePrecision Float16: an unsigned-short array, half the
    memory, ~1/2048 relative precision); the suite's readers take either, and
    ``coordinate_values(array)`` gives float values from either.

    ``model``: a reduction model file (``save_model``) to apply instead of fitting: one
    ``DimensionReduction(Input=source, ModelFile=model)`` (returned twice) computes the
    model's features from the channels it names (matched by name) with the normalisation
    of the volume it was fitted on and places every voxel with the model's references, so
    coordinates (and colours) mean the same as on that volume; `method`, `features` and
    `output_dimension` are then the model's (the arguments are not used). The output also
    holds ModelDistance (above 1.5: outside the model)::

        _, red = mce.reduce_multichannel(volume, "PCA", "6D")
        mce.save_model(red, "brain.mcvmodel")
        _, same = mce.reduce_multichannel(other_volume, model="brain.mcvmodel")

    ``props`` are further DimensionReduction properties (NumberOfNeighbors,
    NumberOfLandmarks, ReferenceSampleSize, RandomSeed, Device). The background is masked
    (MaskBackground, on by default), so the reduction is fitted on foreground voxels;
    ``feats.MaskBackground = 0`` fits on every voxel. Nothing is shown or updated; the
    reduced coordinates are the point array ReducedCoordinates of the reduction's first
    output, its spectrum the second output::

        feats, red = mce.reduce_multichannel(volume, "PCA", "6D", ReferenceSampleSize=5000)
        red.UpdatePipeline(); red.UpdatePropertyInformation()
        print(red.GetPropertyValue("VarianceRetained"), red.GetPropertyValue("Trustworthiness"))
    """
    precision = _PRECISIONS.get(str(coordinate_precision).lower())
    if precision is None:
        raise ValueError("coordinate_precision is 'float32' or 'float16', not %r"
                         % (coordinate_precision,))
    if model is not None:
        from .models import _model_reduction, read_model

        read_model(model)  # a clear error before any pipeline exists
        if keep_features:
            raise ValueError("reduce_multichannel: keep_features is not available with a model "
                             "(the model computes its own features).")
        reduction = _model_reduction(source, model, props)
        reduction.CoordinatePrecision = precision
        return reduction, reduction
    dimension_reduction = _filter("DimensionReduction")
    # Every property set here is recorded in a trace being recorded (the trace replays).
    if features in _PRESETS and not keep_features:
        reduction = dimension_reduction(Input=source)
        with _TracedProperties(reduction):
            reduction.FeatureSet = features
        feats = reduction
    else:
        if features in _PRESETS:
            feats = _filter("MultichannelFeatures")(Input=source)
            with _TracedProperties(feats):
                feats.FeatureSet = features
            array = "Features"
        else:
            feats = source
            array = str(features)
        reduction = dimension_reduction(Input=feats)
        with _TracedProperties(reduction):
            reduction.FeatureSet = "Use input array"
            reduction.Features = ["POINTS", array]
    with _TracedProperties(reduction):
        reduction.Method = method
        reduction.OutputDimension = int(output_dimension)
        reduction.CoordinatePrecision = precision
        for name, value in props.items():
            setattr(reduction, name, value)
    return feats, reduction
