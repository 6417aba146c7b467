"""Dimension reduction of a multichannel volume: MultichannelFeatures followed by
DimensionReduction (PCA, Isomap, LLE) to a 2D/3D domain of reduced coordinates.
"""

from ._common import _filter

__all__ = [
    "reduce_multichannel",
]


def reduce_multichannel(source, method="Isomap", features="24D", output_dimension=3,
                        **props):
    """Feature vectors of a multichannel volume reduced to a 2D/3D domain.

    Builds ``MultichannelFeatures(Input=source, FeatureSet=features)`` followed by
    ``DimensionReduction(Method=method, OutputDimension=output_dimension, **props)`` and
    returns ``(features_proxy, reduction_proxy)``. ``features`` is a preset of
    MultichannelFeatures ("6D", "24D") or the name of a point array of `source` that
    already holds feature vectors (then no MultichannelFeatures filter is made and the
    first proxy returned is `source`). ``props`` are further DimensionReduction
    properties (NumberOfNeighbors, NumberOfLandmarks, ReferenceSampleSize, RandomSeed,
    Device). MultichannelFeatures marks the background (its MaskBackground, on by
    default), so the reduction is fitted on foreground voxels; ``feats.MaskBackground = 0``
    fits on every voxel. Nothing is shown or updated; the reduced coordinates are the point array
    ReducedCoordinates of the reduction's first output, its spectrum the second output::

        feats, red = mce.reduce_multichannel(volume, "PCA", "6D", ReferenceSampleSize=5000)
        red.UpdatePipeline(); red.UpdatePropertyInformation()
        print(red.VarianceRetained, red.Trustworthiness)
    """
    dimension_reduction = _filter("DimensionReduction")
    if features in ("6D", "24D", "Custom"):
        feats = _filter("MultichannelFeatures")(Input=source)
        feats.FeatureSet = features
        array = "Features"
    else:
        feats = source
        array = str(features)
    reduction = dimension_reduction(Input=feats)
    reduction.Features = ["POINTS", array]
    reduction.Method = method
    reduction.OutputDimension = int(output_dimension)
    for name, value in props.items():
        setattr(reduction, name, value)
    return feats, reduction
