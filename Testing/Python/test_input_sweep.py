"""A sweep of bad and edge inputs through every filter, the readers and
the "Gaussian TF Volume" representation. Each row is a clear error (which filter, which
input, what to do) with an empty output, or a documented result (with a warning where the
input is odd); never a crash, a hang (CTest's timeout), NaN in an output array or a
silently wrong picture. Every row also checks that no array the filter wrote holds NaN/Inf.

Filters: BV BestViewpoint, MF MultichannelFeatures, DR DimensionReduction, RD ReducedDomain,
MC MergeChannels, TF the "Gaussian TF Volume" representation, RDR the NIfTI / VolPack .den readers.
Volumes are small and synthetic (a known answer is the point); the real brainsmall.den where
the unit of the spacing matters. "blobs": 20^3, five Gaussian blobs on the plane z = 10 (best
view along z); "coords": 16^3 whose ReducedCoordinates are the voxel position / 15;
"features": 12x10x8 with 4 smooth feature components; W_PLANE: five widgets on the plane
z = 0.5 of "coords".

id                 | fed                              | to  | expected outcome
-------------------+----------------------------------+-----+---------------------------------------
bv.nan-inf         | blobs, 2 NaN + 1 Inf voxels      | BV  | warning "3 voxel(s) hold NaN/Inf";
                   |                                  |     | view along z
bv.all-nan         | 10^3 volume of NaN               | BV  | warning "holds no finite value"; no
                   |                                  |     | view, 0 points
bv.constant        | 10^3 volume of 7                 | BV  | warning "constant"; ViewValid 0,
                   |                                  |     | direction 0
bv.1x1x1           | one voxel                        | BV  | error "fewer than two axes"; empty
bv.line            | 20x1x1 ramp                      | BV  | error "a line or a point has no
                   |                                  |     | view"; empty
bv.thin-z          | 20x20x1 slice of blobs           | BV  | warning "single slice"; view along z
                   |                                  |     | (its normal)
bv.thin-y          | 20x1x20 slice (2D, other axis)   | BV  | warning "single slice"; view along y
bv.spacing-0       | blobs, spacing (0, 1, 1)         | BV  | error "spacing", "axis 0",
                   |                                  |     | "DataSpacing"; empty
bv.spacing-neg     | blobs, spacing (-1, -1, -1)      | BV  | ok: view along z, points mirrored (=
                   |                                  |     | world)
bv.spacing-1e-9    | blobs, spacing 1e-9              | BV  | ok: the direction at spacing 1 (along
                   |                                  |     | z)
bv.spacing-1e-30   | blobs, spacing 1e-30             | BV  | ok: the direction at spacing 1
bv.spacing-1e30    | blobs, spacing 1e30              | BV  | ok: the direction at spacing 1
bv.spacing-aniso   | blobs, spacing (1e-9, 1e-9,      | BV  | ok: along z, as spacing (1, 1, 3)
                   | 3e-9)                            |     |
bv.polydata        | a Sphere (polydata)              | BV  | error "not image data", "resample";
                   |                                  |     | empty
bv.no-channel      | two arrays, no active scalars,   | BV  | ok: both arrays used (= Channels [a,
                   | Channels []                      |     | b])
bv.int8            | blobs x 100 as int8              | BV  | ok: the direction of the same values
                   |                                  |     | as float
bv.uint16          | blobs x 60000 as uint16          | BV  | ok: the direction of the same values
                   |                                  |     | as float
bv.int64           | blobs x 1e12 as int64            | BV  | ok: the direction of the same values
                   |                                  |     | as float
bv.double          | blobs as float64                 | BV  | ok: the direction of the float32
                   |                                  |     | blobs
bv.N-0             | NumberOfInterestPoints 0         | BV  | error "NumberOfInterestPoints",
                   |                                  |     | "positive"; empty
bv.N-neg           | NumberOfInterestPoints -5        | BV  | error "NumberOfInterestPoints",
                   |                                  |     | "positive"; empty
bv.N-1             | NumberOfInterestPoints 1         | BV  | warning "at least 3 interest points"
                   |                                  |     | (once); 1 point
bv.N-huge          | NumberOfInterestPoints 10^6 >    | BV  | warning "fewer than the 1000000";
                   | 8000 voxels                      |     | view along z
bv.sigma-0         | GaussianSigma 0                  | BV  | error "GaussianSigma", "1.5"; empty
bv.sigma-neg       | GaussianSigma -1                 | BV  | error "GaussianSigma", "1.5"; empty
bv.3e38            | blobs + one 3e38 voxel           | BV  | warning "Only 1 of 8000 voxels ...
                   |                                  |     | alone decide the view ... set an
                   |                                  |     | OpacityFunction"
bv.sigma-tiny      | GaussianSigma 1e-9               | BV  | warning "no voxel has a positive
                   |                                  |     | Harris response"
bv.kernel-even     | KernelWidth 4                    | BV  | error "KernelWidth", "odd"; empty
bv.kernel-1        | KernelWidth 1                    | BV  | warning "no voxel has a positive
                   |                                  |     | Harris", not "constant"
bv.kernel-big      | KernelWidth 31 on a 8x8x6 volume | BV  | ok: the direction of KernelWidth 5
                   |                                  |     | (along z)
bv.harrisk-neg     | HarrisK -0.1                     | BV  | error "HarrisK", ">= 0"; empty
bv.harrisk-10      | HarrisK 10                       | BV  | warning "no voxel has a positive
                   |                                  |     | Harris", "HarrisK"
bv.widgets-empty   | OpacitySource Representation, no | BV  | warning "No Gaussian widgets"; no
                   | widgets                          |     | view
bv.widgets-7       | 7 widget values                  | BV  | error "7 values", "multiple of 8";
                   |                                  |     | empty
bv.widgets-sigma0  | a widget of sigma 0              | BV  | error "sigma 0 must be > 0"; empty
bv.widgets-colour  | colours 3.0 (outside [0, 1])     | BV  | warning "clamped"; view along z
bv.widgets-nan     | NaN opacity                      | BV  | error "opacity (number 8"; empty
bv.widgets-10000   | W_PLANE + 9995 widgets far away  | BV  | ok: view along z
bv.toggle          | W_PLANE <-> widgets on x = 0.5,  | BV  | ok: each = a fresh filter's (z, x, z,
                   | 10 times                         |     | ...)
mf.nan-inf         | 10^3 ramp, 1 NaN + 1 Inf         | MF  | warning "2 voxel(s)"; finite features
mf.constant        | 10^3 volume of 7, 24D            | MF  | warning "constant"; features 0; no
                   |                                  |     | "lower" advice
mf.1x1x1           | one voxel                        | MF  | warning "constant"; 2 features of 0
mf.thin            | 20x20x1 slice, 24D               | MF  | warning "gradZ" constant; finite
                   |                                  |     | features
mf.spacing-0       | spacing (0, 1, 1)                | MF  | error "spacing", "axis 0"; empty
mf.spacing-neg     | spacing (-1, -1, -1)             | MF  | ok: the features of spacing 1
mf.spacing-1e-9    | spacing 1e-9 (z-scored)          | MF  | ok: the features of spacing 1
mf.spacing-1e9     | spacing 1e9                      | MF  | ok: the features of spacing 1
mf.values-1e36     | ramp x 1e36 (finite; squares     | MF  | warning "overflow float32" naming
                   | overflow float32)                |     | the columns (values.variance ...),
                   |                                  |     | "rescale the channel"; no NaN
mf.polydata        | a Sphere                         | MF  | error "not image data"; empty
mf.no-channel      | two arrays, Channels []          | MF  | ok: 4 features (= Channels [a, b])
mf.int8            | ramp as int8                     | MF  | ok: the features of the same values
                   |                                  |     | as float
mf.uint16          | ramp as uint16                   | MF  | ok: the features of the same values
                   |                                  |     | as float
mf.int64           | ramp as int64                    | MF  | ok: the features of the same values
                   |                                  |     | as float
mf.double          | ramp as float64                  | MF  | ok: the features of the same values
                   |                                  |     | as float
mf.nifti-4d        | 4D NIfTI (3 time points),        | MF  | ok: 6 features <array>_0.intensity
                   | TimeAsVector                     |     | ...
mf.toggle          | FeatureSet 6D <-> 24D, 10 times  | MF  | ok: each = a fresh filter's
mc.grids           | MergeChannels of blobs (20^3)    | MC  | error "not on one grid" naming input
                   | and ramp (10^3)                  |     | 2 (10 x 10 x 10) and input 1 (20 x 20
                   |                                  |     | x 20), "Resample"; empty
mc.same-grid       | MergeChannels of two 20^3 vols   | MC  | ok: both arrays, 8000 points
dr.ref-0           | ReferenceSampleSize 0            | DR  | error "ReferenceSampleSize",
                   |                                  |     | "positive"; empty
dr.ref-1           | ReferenceSampleSize 1            | DR  | error "ReferenceSampleSize (1)",
                   |                                  |     | "raise"; empty
dr.ref-2           | ReferenceSampleSize 2            | DR  | error "ReferenceSampleSize (2)",
                   |                                  |     | "raise"; empty
dr.ref-huge        | ReferenceSampleSize 10^6 > 960   | DR  | warning "exceeds the number of
                   | voxels                           |     | voxels"; finite
dr.k-0             | Isomap, NumberOfNeighbors 0      | DR  | error "NumberOfNeighbors",
                   |                                  |     | "positive"; empty
dr.k-1-isomap      | Isomap, NumberOfNeighbors 1      | DR  | warning "connected components",
                   |                                  |     | "larger"; finite
dr.k-1-lle         | LLE, NumberOfNeighbors 1         | DR  | warning "connected components";
                   |                                  |     | finite
dr.k-ge-M          | Isomap, K 50 >= 40 reference     | DR  | error "NumberOfNeighbors (50)",
                   | points                           |     | "lower it"; empty
dr.L-0             | Isomap, NumberOfLandmarks 0      | DR  | error "NumberOfLandmarks",
                   |                                  |     | "positive"; empty
dr.L-1-isomap      | Isomap, NumberOfLandmarks 1      | DR  | warning "1 landmarks asked for, 4
                   |                                  |     | used"; finite
dr.L-1-lle         | LLE, NumberOfLandmarks 1         | DR  | warning "1 landmarks asked for, 15
                   |                                  |     | used"; finite
dr.L-above         | Isomap, NumberOfLandmarks 5000 > | DR  | warning "5000 landmarks asked for,
                   | M 300                            |     | 300 used"
dr.L-above-lle     | LLE, NumberOfLandmarks 5000 > M  | DR  | ok: exact LLE (documented: L >= M)
                   | 300                              |     |
dr.dim-0           | OutputDimension 0                | DR  | error "OutputDimension", "2 or 3";
                   |                                  |     | empty
dr.dim-1           | OutputDimension 1                | DR  | error "OutputDimension", "2 or 3";
                   |                                  |     | empty
dr.dim-2           | OutputDimension 2                | DR  | ok: 2 components dim1, dim2
dr.dim-10          | OutputDimension 10               | DR  | error "OutputDimension", "2 or 3";
                   |                                  |     | empty
dr.nan             | NaN in one Features value        | DR  | error "non-finite", "voxel 5"; empty
dr.constant        | Features all 2.0                 | DR  | error "0 of the 4 feature components
                   |                                  |     | vary"; empty
dr.1x1x1           | one voxel of features            | DR  | error "vary"; empty
dr.no-feature      | no Features array, Features '',  | DR  | error "No feature array selected";
                   | FeatureSet "Use input array"     |     | empty
dr.no-feature-auto | no Features array, FeatureSet    | DR  | features from the channels (the
                   | Automatic (the default)          |     | fused path): finite 3D coordinates,
                   |                                  |     | warning "values_0.gradZ" constant
dr.polydata        | a Sphere                         | DR  | error "not image data"; empty
dr.int64           | features x 1000 as int64         | DR  | ok: finite 3D coordinates
dr.int8            | features x 40 as int8            | DR  | ok: finite 3D coordinates
dr.toggle          | Method PCA <-> Isomap, 10 times  | DR  | ok: each = a fresh filter's
rd.nan-coords      | coords with NaN for x > 0.8      | RD  | warning "768 point(s)", "NaN"; 3328
                   |                                  |     | finite points
rd.all-nan         | every coordinate NaN             | RD  | error "No point has finite"; empty
rd.constant-seed   | one distinct coordinate,         | RD  | warning "1 distinct"; 512 points, no
                   | SeedWidgetCount 2                |     | seeded widget
rd.1x1x1           | one voxel, SeedWidgetCount 1 (no | RD  | ok: 1 point, 1 seeded widget
                   | skip)                            |     |
rd.1-component     | 1-component coordinates          | RD  | error "1 component(s)", "2 or 3";
                   |                                  |     | empty
rd.polydata        | a Sphere without coordinates     | RD  | error "no coordinates array",
                   |                                  |     | "DimensionReduction"
rd.polydata-coords | a Sphere with ReducedCoordinates | RD  | ok: its 50 points
                   | (any set)                        |     |
rd.widgets-empty   | no widgets                       | RD  | warning "No Gaussian widgets"; RGBA
                   |                                  |     | all 0
rd.widgets-7       | 7 widget values                  | RD  | error "multiple of 8"; empty
rd.widgets-sigma0  | sigma -0.1                       | RD  | error "must be > 0"; empty
rd.widgets-colour  | colours -3 (outside [0, 1])      | RD  | warning "clamped"; RGBA in range
rd.widgets-nan     | NaN opacity                      | RD  | error "opacity (number 8"; empty
rd.widgets-10000   | W_PLANE + 9995 far widgets       | RD  | ok: RGBA = that of W_PLANE alone
rd.toggle          | widgets red <-> green, 10 times  | RD  | ok: each = a fresh filter's RGBA
tf.nan-coords      | coords with NaN for x > 0.8      | TF  | ok: NaN voxels transparent, the rest
                   |                                  |     | drawn
tf.constant        | every voxel at the red widget's  | TF  | ok: drawn red
                   | centre                           |     |
tf.1x1x1           | one voxel                        | TF  | ok: no crash, valid
tf.thin            | 16x16x1 slice                    | TF  | ok: drawn
tf.spacing-0       | coords, spacing 0                | TF  | error "spacing", "axis 0"; nothing
                   |                                  |     | drawn
tf.spacing-neg     | coords, spacing -1               | TF  | error "negative spacing", "Resample
                   |                                  |     | To Image"
tf.spacing-1e-9    | faint widgets, spacing 1e-9, per | TF  | ok: the picture at spacing 1 (was
                   | sample                           |     | blank)
tf.spacing-1e9     | faint widgets, spacing 1e9, per  | TF  | ok: the picture at spacing 1
                   | sample                           |     |
tf.spacing-1e-9-v  | faint widgets, spacing 1e-9, per | TF  | ok: the picture at spacing 1 (was
                   | voxel                            |     | saturated)
tf.spacing-1e9-v   | faint widgets, spacing 1e9, per  | TF  | ok: the picture at spacing 1 (was
                   | voxel                            |     | blank)
tf.int16           | int16 coordinates (x 100)        | TF  | ok: drawn red at the red widget
tf.widgets-empty   | no widgets (after some)          | TF  | warning "transparent"; nothing drawn
tf.widgets-7       | 7 widget values                  | TF  | error "multiple of 8"; nothing drawn
tf.widgets-sigma0  | sigma 0                          | TF  | error "must be > 0"; nothing drawn
tf.widgets-sigma-  | sigma -1                         | TF  | error "must be > 0"; nothing drawn
tf.widgets-colour  | colour (3, -1, 0), opacity 7     | TF  | warning "clamped"; drawn red
tf.widgets-nan     | NaN opacity                      | TF  | error "opacity (number 8"; nothing
                   |                                  |     | drawn
tf.widgets-10000   | 10 000 widgets, per sample       | TF  | error "at most 64", "Per voxel";
                   |                                  |     | nothing drawn
tf.widgets-10000-v | 10 000 widgets, per voxel        | TF  | ok: drawn as the 2 visible widgets
tf.toggle          | widgets red <-> green, 10 times  | TF  | ok: each picture = a fresh display's
tf.polydata        | a Sphere (polydata)              | TF  | not offered (image data only)
rdr.nifti-4d       | 4D NIfTI written by              | RDR | ok: 3 components (TimeAsVector),
                   | vtkNIFTIImageWriter              |     | values kept
rdr.nifti-4d-first | the same, TimeAsVector 0         | RDR | ok: 1 component, the first volume
rdr.nifti-int8     | int8 NIfTI                       | RDR | ok: int8 values read back
rdr.nifti-uint16   | uint16 NIfTI                     | RDR | ok: uint16 values read back
rdr.nifti-int64    | int64 NIfTI                      | RDR | ok: int64 values read back
rdr.nifti-double   | float64 NIfTI                    | RDR | ok: float64 values read back
bv.nifti-4d        | the 4D NIfTI, 3 channels         | BV  | ok: a view (the maximum of the 3
                   |                                  |     | opacities)
rdr.den-spacing    | brainsmall.den at spacing 1e-9,  | BV  | ok: the direction at spacing 1 (real
                   | 1e-12, 1e9                       |     | brain)
rdr.den-spacing-0  | brainsmall.den, DataSpacing (0,  | RDR | error naming the file, "spacing 0
                   | 1, 1)                            |     | along axis 1", DataSpacing; empty

Already covered elsewhere (not repeated here): test_bad_inputs (no point array, missing
array name, empty extent, one-node opacity function, broken .den files, memory limits),
test_reduction (one component, K >= M on the brain, constant feature column, int16),
test_features (Custom with nothing selected, GPU fallback), test_widget_viewpoint
(ReducedDomain SampleSize 0/-1, SeedWidgetCount 65, SeedWidgetOpacity NaN/1.5, NaN widget
coordinates in BestViewpoint), test_gaussian_tf_representation (missing / 1-component
coordinate array, 65 widgets), test_nifti_reader (truncated / corrupt / impossible NIfTI).

Also elsewhere: two MPI ranks on a volume with fewer slices than ranks (test_mpi.sh: a 2x2x2
volume on 2 and 4 processes equals one process); an address-space limit (test_features).

PENDING (expected outcomes another change delivers; listed in PENDING below, not asserted):
pending.overflow   | ramp at spacing 1e-30: gradMag   | MF  | the features of spacing 1 (today the
                   | squares overflow float32         |     | overflow warning, gradMag 0)
pending.underflow  | spacing 1e30: gradMag squares    | MF  | the features of spacing 1 (today
                   | underflow                        |     | gradMag = 0, "constant")
"""
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import gaussian_tf_testing as G  # noqa: E402
import builtins as B  # noqa: E402  (paraview.simple's * import would shadow max/min/sum)

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_input_sweep")

from vtkmodules import vtkCommonCore as CC  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402

ARRAY_TYPES = {"float": CC.vtkFloatArray, "double": CC.vtkDoubleArray,
               "int8": CC.vtkSignedCharArray, "uint16": CC.vtkUnsignedShortArray,
               "int16": CC.vtkShortArray, "int64": CC.vtkLongLongArray}
FILTERS = {"BV": "BestViewpoint", "MF": "MultichannelFeatures", "DR": "DimensionReduction",
           "RD": "ReducedDomain", "MC": "MergeChannels"}
CLASSES = {"BV": "vtkBestViewpoint", "MF": "vtkMultichannelFeatures", "MC": "vtkMergeChannels",
           "DR": "vtkDimensionReduction", "RD": "vtkReducedDomain",
           "TF": "vtkGaussianTFVolumeRepresentation"}
TMP = tempfile.mkdtemp(prefix="mcv_sweep_")


# ---- synthetic volumes ----------------------------------------------------------------------
def image(dims, arrays, spacing=(1.0, 1.0, 1.0), active=True):
    """vtkImageData of `dims` with point arrays [(name, f(i, j, k, c), components, type)];
    the first is the active scalars when `active`."""
    data = vtkImageData()
    data.SetDimensions(*dims)
    data.SetSpacing(*spacing)
    n = dims[0] * dims[1] * dims[2]
    for name, f, components, kind in arrays:
        a = ARRAY_TYPES[kind]()
        a.SetName(name)
        a.SetNumberOfComponents(components)
        a.SetNumberOfTuples(n)
        t = 0
        for k in range(dims[2]):
            for j in range(dims[1]):
                for i in range(dims[0]):
                    for c in range(components):
                        a.SetComponent(t, c, f(i, j, k, c))
                    t += 1
        data.GetPointData().AddArray(a)
    if active and arrays:
        data.GetPointData().SetActiveScalars(arrays[0][0])
    return data


def producer(data):
    """A pipeline source delivering `data` (pvbatch: a built-in session, same process)."""
    source = simple.PVTrivialProducer()
    source.GetClientSideObject().SetOutput(data)
    source.UpdatePipeline()
    return source


def scalar(dims, f, spacing=(1.0, 1.0, 1.0), kind="float", name="values"):
    return image(dims, [(name, f, 1, kind)], spacing)


def blobs(i, j, k, c=0):
    """Five Gaussian blobs on the plane z = 10 of a 20^3 volume: the best view is along z."""
    v = 0.0
    for cx, cy in ((5, 5), (5, 14), (14, 5), (14, 14), (10, 10)):
        v += math.exp(-((i - cx) ** 2 + (j - cy) ** 2 + (k - 10) ** 2) / 3.0)
    return v


def ramp(i, j, k, c=0):
    """A varied, exactly representable pattern (integers 0..100) for the type rows."""
    return float((i * 7 + j * j + 3 * k + 11 * c) % 101)


def smooth(i, j, k, c):
    return math.sin(0.3 * i + c) + math.cos(0.2 * j * (c + 1)) + 0.1 * k * c


def coords(i, j, k, c, n=16):
    return (i, j, k)[c] / (n - 1.0)


def nan_if(cond, value):
    return float("nan") if cond else value


def widgets_on_plane(axis, colour=(1.0, 0.5, 0.2)):
    """Five widgets on the plane <axis> = 0.5 of "coords" (its normal is the best view)."""
    flat = []
    for u, v in ((0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75), (0.5, 0.5)):
        centre = [u, v]
        centre.insert(axis, 0.5)
        flat += centre + [0.08] + list(colour) + [1.0]
    return flat


W_PLANE = widgets_on_plane(2)
W_PLANE_X = widgets_on_plane(0)
FAR = [5.0, 5.0, 5.0, 0.05, 1.0, 1.0, 1.0, 1.0]  # far outside [0, 1]^3: no voxel sees it
RED = [0.25, 0.5, 0.5, 0.15, 1, 0, 0, 1]
GREEN = [0.75, 0.5, 0.5, 0.15, 0, 1, 0, 1]
# Faint widgets: the picture does not saturate, so a wrong opacity scale shows.
FAINT = {"GaussianWidgets": RED[:7] + [0.05] + GREEN[:7] + [0.05]}


def write_nifti(name, data, time_points=1):
    from vtkmodules.vtkIOImage import vtkNIFTIImageWriter

    path = os.path.join(TMP, name)
    writer = vtkNIFTIImageWriter()
    writer.SetInputData(data)
    if time_points > 1:
        writer.SetTimeDimension(time_points)
    writer.SetFileName(path)
    writer.Write()
    return path


def make_volumes():
    V = {}
    V["blobs"] = lambda: scalar((20, 20, 20), blobs)
    V["blobs-naninf"] = lambda: scalar(
        (20, 20, 20), lambda i, j, k, c: float("inf") if (i, j, k) == (18, 2, 4) else
        nan_if((i, j) == (2, 2) and k in (3, 17), blobs(i, j, k)))
    V["nan"] = lambda: scalar((10, 10, 10), lambda *a: float("nan"))
    V["constant"] = lambda: scalar((10, 10, 10), lambda *a: 7.0)
    V["1x1x1"] = lambda: scalar((1, 1, 1), lambda *a: 1.0)
    V["line"] = lambda: scalar((20, 1, 1), lambda i, j, k, c: float(i))
    V["thin-z"] = lambda: scalar((20, 20, 1), lambda i, j, k, c: blobs(i, j, 10))
    V["thin-y"] = lambda: scalar((20, 1, 20), lambda i, j, k, c: blobs(i, 10, k))
    for label, s in (("0", (0, 1, 1)), ("neg", (-1, -1, -1)), ("1e-9", (1e-9,) * 3),
                     ("1e-30", (1e-30,) * 3), ("1e30", (1e30,) * 3), ("1e9", (1e9,) * 3),
                     ("aniso", (1e-9, 1e-9, 3e-9)), ("1-1-3", (1, 1, 3))):
        V["blobs-spacing-" + label] = (lambda s=s: scalar((20, 20, 20), blobs, spacing=s))
        V["ramp-spacing-" + label] = (lambda s=s: scalar((10, 10, 10), ramp, spacing=s))
    V["two-arrays"] = lambda: image((20, 20, 20), [
        ("a", lambda i, j, k, c: blobs(i, j, k) if i < 10 else 0.0, 1, "float"),
        ("b", lambda i, j, k, c: blobs(i, j, k) if i >= 10 else 0.0, 1, "float")], active=False)
    for kind, scale in (("int8", 100.0), ("uint16", 60000.0), ("int64", 1e12), ("double", 1.0)):
        V["blobs-" + kind] = (lambda kind=kind, scale=scale: scalar(
            (20, 20, 20), lambda i, j, k, c: round(scale * blobs(i, j, k)) if scale != 1 else
            blobs(i, j, k), kind=kind))
        V["blobs-" + kind + "-as-float"] = (lambda kind=kind, scale=scale: scalar(
            (20, 20, 20), lambda i, j, k, c: round(scale * blobs(i, j, k)) if scale != 1 else
            blobs(i, j, k)))
        V["ramp-" + kind] = (lambda kind=kind: scalar((10, 10, 10), ramp, kind=kind))
    V["ramp"] = lambda: scalar((10, 10, 10), ramp)
    V["ramp-1e36"] = lambda: scalar((10, 10, 10), lambda i, j, k, c: 1e36 * ramp(i, j, k))
    V["blobs-3e38"] = lambda: scalar((20, 20, 20), lambda i, j, k, c: 3e38 if (i, j, k) == (
        3, 17, 5) else blobs(i, j, k))
    V["ramp-naninf"] = lambda: scalar((10, 10, 10), lambda i, j, k, c: float("inf") if
                                       (i, j, k) == (9, 9, 9) else nan_if((i, j, k) == (1, 2, 3),
                                                                          ramp(i, j, k)))
    V["coords"] = lambda: image((16, 16, 16), [("ReducedCoordinates", coords, 3, "float")])
    V["coords-nan"] = lambda: image((16, 16, 16), [(
        "ReducedCoordinates", lambda i, j, k, c: nan_if(i > 12, coords(i, j, k, c)), 3, "float")])
    V["coords-allnan"] = lambda: image((4, 4, 4), [
        ("ReducedCoordinates", lambda *a: float("nan"), 3, "float")])
    V["coords-constant"] = lambda: image((8, 8, 8), [
        ("ReducedCoordinates", lambda i, j, k, c: RED[c], 3, "float")])
    V["coords-1x1x1"] = lambda: image((1, 1, 1), [
        ("ReducedCoordinates", lambda i, j, k, c: RED[c], 3, "float")])
    V["coords-1comp"] = lambda: image((8, 8, 8), [
        ("ReducedCoordinates", lambda i, j, k, c: float(i), 1, "float")])
    V["coords-thin"] = lambda: image((16, 16, 1), [
        ("ReducedCoordinates", lambda i, j, k, c: coords(i, j, 8, c), 3, "float")])
    for label, s in (("0", (0, 0, 0)), ("neg", (-1, -1, -1)), ("1e-9", (1e-9,) * 3),
                     ("1e9", (1e9,) * 3)):
        V["coords-spacing-" + label] = (lambda s=s: image(
            (16, 16, 16), [("ReducedCoordinates", coords, 3, "float")], spacing=s))
    V["coords-int16"] = lambda: image((16, 16, 16), [
        ("ReducedCoordinates", lambda i, j, k, c: round(100 * coords(i, j, k, c)), 3, "int16")])
    V["features"] = lambda: image((12, 10, 8), [("Features", smooth, 4, "float")])
    V["features-nan"] = lambda: image((12, 10, 8), [(
        "Features", lambda i, j, k, c: nan_if((i, j, k, c) == (5, 0, 0, 2), smooth(i, j, k, c)),
        4, "float")])
    V["features-constant"] = lambda: image((12, 10, 8), [("Features", lambda *a: 2.0, 4,
                                                          "float")])
    V["features-1x1x1"] = lambda: image((1, 1, 1), [("Features", smooth, 4, "float")])
    V["features-none"] = lambda: image((12, 10, 8), [("values", smooth, 4, "float")])
    V["features-int64"] = lambda: image((12, 10, 8), [(
        "Features", lambda i, j, k, c: round(1000 * smooth(i, j, k, c)), 4, "int64")])
    V["features-int8"] = lambda: image((12, 10, 8), [(
        "Features", lambda i, j, k, c: round(40 * smooth(i, j, k, c)), 4, "int8")])
    return V


VOLUME_MAKERS = make_volumes()
_sources = {}


def source(key):
    """The pipeline source of volume `key` (made once); "sphere": a Sphere (polydata, 50
    points), "sphere-coords": the same with its point coordinates as ReducedCoordinates."""
    if key not in _sources:
        if key == "sphere":
            _sources[key] = simple.Sphere()
        elif key == "sphere-coords":
            _sources[key] = simple.Calculator(Input=source("sphere"), Function="coords",
                                              ResultArrayName="ReducedCoordinates")
        else:
            _sources[key] = producer(VOLUME_MAKERS[key]())
        _sources[key].UpdatePipeline()
    return _sources[key]


# ---- what a row looks at --------------------------------------------------------------------
def non_finite_arrays(data_objects, skip=()):
    """Names of the float arrays (point, cell, field data; table rows) of `data_objects` that
    hold NaN/Inf, except the names in `skip` (the input's own arrays, passed through)."""
    bad = []
    for data in data_objects:
        if data is None:
            continue
        collections = [data.GetFieldData()]
        for getter in ("GetPointData", "GetCellData", "GetRowData"):
            if hasattr(data, getter):
                collections.append(getattr(data, getter)())
        for fd in collections:
            for a in range(fd.GetNumberOfArrays()):
                array = fd.GetArray(a)
                if array is None or array.GetName() in skip or array.GetNumberOfTuples() == 0:
                    continue
                code = {CC.VTK_FLOAT: "f", CC.VTK_DOUBLE: "d"}.get(array.GetDataType())
                if code is None:
                    continue  # integers cannot hold NaN
                if not B.all(map(math.isfinite, memoryview(array).cast("B").cast(code))):
                    bad.append(array.GetName())
    return bad


def values_of(array):
    """A copy of every value of a vtk array (component-interleaved), as Python floats."""
    if array is None:
        return None
    n = array.GetNumberOfTuples() * array.GetNumberOfComponents()
    return [array.GetValue(i) if hasattr(array, "GetValue") else array.GetVariantValue(i)
            for i in range(n)]


class Outcome(object):
    """What one run of a row left: messages, outputs, the filter's read-back values."""

    def __init__(self, errors, warnings, outputs, props, empty, non_finite, **extra):
        self.errors = list(errors)
        self.warnings = list(warnings)
        self.outputs = outputs
        self.props = props
        self.empty = empty
        self.non_finite = non_finite
        self.__dict__.update(extra)

    @property
    def best(self):
        return [float(x) for x in self.props.get("BestViewDirection", [0, 0, 0])]

    @property
    def valid(self):
        return int(self.props.get("ViewValid", 0)) == 1

    def array(self, name, port=0):
        data = self.outputs[port]
        return data.GetPointData().GetArray(name) if data is not None else None


READ_BACK = {
    "BV": ("ViewValid", "BestViewDirection", "NumberOfPointsFound", "NumberOfNonFiniteVoxels",
           "EigenvalueSpectrum"),
    "MF": ("NumberOfFeatures", "NumberOfNonFiniteVoxels"),
    "DR": ("EigenvalueSpectrum", "VarianceRetained", "Trustworthiness"),
    "RD": ("SeededWidgets",),
    "MC": (),
}


def is_empty(to, outputs, props):
    points = [o.GetNumberOfPoints() if o is not None and hasattr(o, "GetNumberOfPoints") else 0
              for o in outputs]
    if to == "BV":
        return points[0] == 0 and int(props["ViewValid"]) == 0
    if to == "MF":
        return points[0] == 0 and outputs[0].GetPointData().GetArray("Features") is None
    if to == "DR":
        return points[0] == 0 and outputs[1].GetNumberOfRows() == 0
    return B.all(p == 0 for p in points)


def run_filter(row, proxy=None):
    """Runs row.to on row.source with row.props (a fresh filter unless `proxy` is given)."""
    src = source(row.source)
    if proxy is None:
        proxy = getattr(simple, FILTERS[row.to])(Input=src)
    msgs = T.Messages(proxy)
    for name, value in row.props.items():
        setattr(proxy, name, value)
    proxy.UpdatePipeline()
    proxy.UpdatePropertyInformation()
    algorithm = proxy.GetClientSideObject()
    outputs = [algorithm.GetOutputDataObject(p) for p in range(algorithm.GetNumberOfOutputPorts())]
    props = {}
    for name in READ_BACK[row.to]:
        value = proxy.GetPropertyValue(name)
        props[name] = list(value) if hasattr(value, "__len__") else value
    input_data = src.GetClientSideObject().GetOutputDataObject(0)
    skip = [input_data.GetPointData().GetArrayName(a)
            for a in range(input_data.GetPointData().GetNumberOfArrays())] \
        if hasattr(input_data, "GetPointData") else []
    outcome = Outcome(msgs.errors, msgs.warnings, outputs, props, is_empty(row.to, outputs, props),
                      non_finite_arrays(outputs, skip), proxy=proxy)
    return outcome


def fetch_values(outcome, name, port=0):
    return values_of(outcome.array(name, port))


# ---- the representation ---------------------------------------------------------------------
SHOT_SIZE = (160, 160)


def render_tf(src, props, before=None, label="tf", view=None):
    """Shows `src` as a Gaussian TF Volume seen along -z, with `before` (rendered first) and
    then `props`; returns (view, display, messages, shot, info)."""
    view = view or G.black_view(SHOT_SIZE)
    display = simple.Show(src, view)
    display.SetRepresentationType("Gaussian TF Volume")
    display.ShowWidgetLegend = 0  # the pixel checks look at the volume, not at the legend
    msgs = G.messages(display)
    bounds = src.GetDataInformation().GetBounds()
    if any(bounds[2 * a + 1] <= bounds[2 * a] for a in range(2)):
        bounds = [0, 15, 0, 15, 0, 15]  # a degenerate volume: any camera
    if before:
        for name, value in before.items():
            setattr(display, name, value)
        G.look_down_z(view, bounds)
        msgs.clear()
    for name, value in props.items():
        setattr(display, name, value)
    G.look_down_z(view, bounds)
    shot = G.Shot(view, G.output_path("sweep_%s.png" % label))
    return view, display, msgs, shot, G.info(display)


def run_tf(row):
    props = dict(row.props)
    props.setdefault("GaussianWidgets", RED + GREEN)
    src = source(row.source)
    view, display, msgs, shot, info = render_tf(src, props, row.before, row.id)
    b = src.GetDataInformation().GetBounds()

    def world(u):  # a point of the volume given as a fraction of its bounds
        return [b[2 * a] + (b[2 * a + 1] - b[2 * a]) * u[a] for a in range(3)]
    pixel = {name: shot.rgb(G.project(view, world(at)))
             for name, at in (("red", RED[:3]), ("green", GREEN[:3]), ("centre", [0.5] * 3),
                              ("nan-side", [14 / 15.0, 0.5, 0.5]))}
    outcome = Outcome(msgs.errors, msgs.warnings, [], info,
                      info["valid"] == 0 and shot.max_channel() <= 10, [],
                      shot=shot, pixel=pixel, drawn=shot.max_channel() > 10)
    simple.Delete(view)
    return outcome


# ---- the readers ------------------------------------------------------------------------------
def run_reader(path, proxy_name, **props):
    reader = getattr(simple, proxy_name)()
    msgs = T.Messages(reader)  # before FileName: its first read is observed
    for name, value in props.items():
        setattr(reader, name, value)
    reader.FileName = path
    reader.UpdatePipeline()
    data = reader.GetClientSideObject().GetOutputDataObject(0)
    outcome = Outcome(msgs.errors, msgs.warnings, [data], {}, data.GetNumberOfPoints() == 0,
                      non_finite_arrays([data]), proxy=reader, data=data)
    return outcome


# ---- the table -------------------------------------------------------------------------------
# The warning of MultichannelFeatures (and DimensionReduction's own features) on one channel.
ONE_CHANNEL = ("Only one channel", "Merge Channels")


class Row(object):
    def __init__(self, id, to, source, props=None, expect="ok", words=(), check=None,
                 runner=None, before=None):
        self.id, self.to, self.source = id, to, source
        self.props = props or {}
        self.expect, self.words, self.check = expect, tuple(words), check
        self.runner, self.before = runner, before


RESULTS = {}  # row id -> Outcome (rows compare with earlier rows)


def along(axis, tolerance_deg=1.0):
    def check(o):
        d = o.best
        e = [0.0, 0.0, 0.0]
        e[axis] = 1.0
        angle = T.angle_deg(d, e, unsigned=True) if T.norm(d) > 0 else 180.0
        return o.valid and angle < tolerance_deg, "view along %s %s (%.2f deg)" % (
            "xyz"[axis], ["%.3f" % x for x in d], angle)
    return check


def same_direction_as(other, tolerance_deg=0.5):
    def check(o):
        ref = RESULTS[other].best
        angle = T.angle_deg(o.best, ref, unsigned=True) if T.norm(o.best) > 0 else 180.0
        return o.valid and angle < tolerance_deg, "direction %s = %s's %s (%.3f deg)" % (
            ["%.3f" % x for x in o.best], other, ["%.3f" % x for x in ref], angle)
    return check


def same_values(name, other, tolerance=1e-4, port=0):
    def check(o):
        mine, theirs = fetch_values(o, name, port), RESULTS[other].values
        if mine is None or theirs is None or len(mine) != len(theirs):
            return False, "%s: %s values, %s has %s" % (
                name, None if mine is None else len(mine), other,
                None if theirs is None else len(theirs))
        worst = B.max([B.abs(a - b) for a, b in zip(mine, theirs)] or [0.0])
        return worst <= tolerance, "%s = %s's (max difference %.2g)" % (name, other, worst)
    return check


def keep_values(name, port=0):
    """Stores the row's `name` values for later rows (and checks they exist)."""
    def check(o):
        o.values = fetch_values(o, name, port)
        return o.values is not None, "%s: %s values" % (
            name, None if o.values is None else len(o.values))
    return check


def all_of(*checks):
    def check(o):
        results = [c(o) for c in checks]
        return B.all(r[0] for r in results), "; ".join(r[1] for r in results)
    return check


def cond(predicate, text):
    return lambda o: (predicate(o), text)


def n_features(count, first_name=None):
    def check(o):
        a = o.array("Features")
        names = [a.GetComponentName(c) for c in range(a.GetNumberOfComponents())] if a else []
        ok = a is not None and a.GetNumberOfComponents() == count and (
            first_name is None or (names and names[0] == first_name))
        return ok, "Features has %s components %s" % (
            a.GetNumberOfComponents() if a else None, names[:3])
    return check


def coordinates_ok(dim):
    def check(o):
        a = o.array("ReducedCoordinates")
        ok = a is not None and a.GetNumberOfComponents() == dim and \
            a.GetNumberOfTuples() == o.outputs[0].GetNumberOfPoints() > 0
        return ok, "ReducedCoordinates: %s components, %s tuples" % (
            a.GetNumberOfComponents() if a else None, a.GetNumberOfTuples() if a else None)
    return check


def points(count, port=0):
    return cond(lambda o: o.outputs[port].GetNumberOfPoints() == count,
                "%d output points" % count)


def pixel_is(name, channel, minimum=60):
    def check(o):
        rgb = o.pixel[name]
        return G.is_colour(rgb, channel, minimum), "pixel at the %s widget %s" % (name, rgb)
    return check


def keep_pixels(o):
    o.values = [v for name in ("red", "green", "centre") for v in o.pixel[name]]
    return True, "pixels %s" % o.values


def same_pixels(other, tolerance=8):
    def check(o):
        mine = [v for name in ("red", "green", "centre") for v in o.pixel[name]]
        worst = B.max(B.abs(a - b) for a, b in zip(mine, RESULTS[other].values))
        return worst <= tolerance, "pixels at the widgets and the centre %s = %s's %s (%d)" % (
            mine, other, RESULTS[other].values, worst)
    return check


def drawn(o):
    return o.drawn and o.props["valid"] == 1, "drawn (max pixel %d), valid" % o.shot.max_channel()


def rgba_range(o):
    a = o.array("RGBA")
    return a is not None and a.GetNumberOfTuples() > 0, "RGBA: %s tuples" % (
        a.GetNumberOfTuples() if a else None)


# ---- a property changed back and forth ----------------------------------------------------------
def toggle(to, src, prop, values, read, fixed=None, changes=10):
    """Changes `prop` of one filter `changes` times between `values`; after each change its
    output (read(outcome)) must equal that of a fresh filter made with the same value."""
    def runner(row):
        proxy = getattr(simple, FILTERS[to])(Input=source(src))
        mismatches, errors, warnings, non_finite = [], [], [], []
        for n in range(changes):
            props = dict(fixed or {})
            props[prop] = values[n % len(values)]
            step = Row(row.id, to, src, props)
            mine = run_filter(step, proxy)
            fresh = run_filter(step)
            a, b = read(mine), read(fresh)
            if a != b:
                mismatches.append("change %d (%s): %s != fresh %s" % (n, props[prop], a, b))
            errors += mine.errors
            warnings += mine.warnings
            non_finite += mine.non_finite + fresh.non_finite
            simple.Delete(fresh.proxy)
        simple.Delete(proxy)
        return Outcome(errors, warnings, [None], {}, False, non_finite, mismatches=mismatches)
    return runner


def toggle_tf(changes=10):
    def runner(row):
        view, display, msgs, shot, info = render_tf(source("coords"), {"GaussianWidgets": RED},
                                                    label="toggle")
        mismatches = []
        for n in range(changes):
            widgets = (GREEN, RED)[n % 2]
            display.GaussianWidgets = widgets
            simple.Render(view)
            mine = G.Shot(view, G.output_path("sweep_toggle.png"))
            fresh_view, _, _, fresh, _ = render_tf(source("coords"), {"GaussianWidgets": widgets},
                                                   label="toggle_fresh")
            simple.Delete(fresh_view)
            worst = B.max(B.abs(a - b) for a, b in zip(memoryview(mine.scalars).cast("B"),
                                                        memoryview(fresh.scalars).cast("B")))
            if worst > 8:
                mismatches.append("change %d: pixels differ by up to %d" % (n, worst))
        outcome = Outcome(msgs.errors, msgs.warnings, [], G.info(display), False, [],
                          mismatches=mismatches)
        simple.Delete(view)
        return outcome
    return runner


def offered_for(row):
    """Whether "Gaussian TF Volume" is among the representations of row.source's display."""
    view = G.black_view(SHOT_SIZE)
    display = simple.Show(source(row.source), view)
    available = list(display.GetProperty("Representation").Available)
    simple.Delete(view)
    return Outcome([], [], [], {}, False, [], offered="Gaussian TF Volume" in available,
                   available=available)


def no_mismatch(o):
    return not o.mismatches, "every change = a fresh one %s" % (o.mismatches[:2] or "")


def direction_of(o):
    return [round(x, 4) for x in o.best] + [o.valid]


def rounded_values(name):
    return lambda o: [round(v, 4) for v in (fetch_values(o, name) or [])]


# ---- the readers' rows ------------------------------------------------------------------------
def nifti_rows():
    """4D and typed NIfTI files written with vtkNIFTIImageWriter, read back."""
    four_d = image((8, 8, 6), [("values", lambda i, j, k, c: blobs(2 * i + 2, 2 * j + 2, k + 7) *
                                (c + 1), 3, "float")])
    path_4d = write_nifti("four_d.nii", four_d, time_points=3)

    def reader_runner(path, check_array, **props):
        def runner(row):
            o = run_reader(path, "NIfTIImageReader", **props)
            o.checked = check_array(o.data.GetPointData().GetScalars())
            return o
        return runner

    def components_and_values(count, expected):
        def check_array(array):
            if array is None:
                return False, "no point array"
            got = [array.GetComponent(t, c) for t in (0, 100, 287) for c in range(count)]
            want = [expected(t, c) for t in (0, 100, 287) for c in range(count)]
            ok = array.GetNumberOfComponents() == count and B.all(
                B.abs(a - b) <= 1e-5 * B.max(1.0, B.abs(b)) for a, b in zip(got, want))
            return ok, "%d component(s), values kept (%s)" % (array.GetNumberOfComponents(),
                                                             got[:3])
        return check_array

    source_values = four_d.GetPointData().GetArray("values")
    rows = [
        Row("rdr.nifti-4d", "RDR", None, runner=reader_runner(
            path_4d, components_and_values(3, source_values.GetComponent), TimeAsVector=1),
            check=lambda o: o.checked),
        Row("rdr.nifti-4d-first", "RDR", None, runner=reader_runner(
            path_4d, components_and_values(1, source_values.GetComponent), TimeAsVector=0),
            check=lambda o: o.checked),
    ]
    for kind, scale, vtk_type in (("int8", 100.0, CC.VTK_SIGNED_CHAR),
                                  ("uint16", 60000.0, CC.VTK_UNSIGNED_SHORT),
                                  ("int64", 1e12, CC.VTK_LONG_LONG),
                                  ("double", 1.0, CC.VTK_DOUBLE)):
        data = scalar((12, 12, 8), lambda i, j, k, c, s=scale: round(s * blobs(i + 4, j + 4, k + 6))
                      if s != 1 else blobs(i + 4, j + 4, k + 6), kind=kind)
        path = write_nifti("typed_%s.nii" % kind, data)
        array = data.GetPointData().GetScalars()

        def typed_check(got, array=array, vtk_type=vtk_type):
            ok, text = components_and_values(1, array.GetComponent)(got)
            return ok and got.GetDataType() == vtk_type, "type %s; %s" % (
                got.GetDataTypeAsString() if got else None, text)
        rows.append(Row("rdr.nifti-" + kind, "RDR", None, runner=reader_runner(path, typed_check),
                        check=lambda o: o.checked))

    def channels_runner(row):
        reader = simple.NIfTIImageReader(FileName=path_4d, TimeAsVector=1)
        reader.UpdatePipeline()
        _sources["nifti-4d"] = reader
        return run_filter(row)
    rows.append(Row("bv.nifti-4d", "BV", "nifti-4d", {"NumberOfInterestPoints": 100},
                    runner=channels_runner, check=along(2, 5.0)))
    rows.append(Row("mf.nifti-4d", "MF", "nifti-4d", {"FeatureSet": "6D"},
                    check=n_features(6, "four_d_0.intensity")))
    return rows


def den_rows():
    path = T.data_file("brainsmall.den")

    def bv_at(spacing):
        reader = simple.VolPackDenReader(FileName=path, DataSpacing=spacing)
        bvp = simple.BestViewpoint(Input=reader)
        msgs = T.Messages(bvp)
        bvp.UpdatePipeline()
        bvp.UpdatePropertyInformation()
        direction = [float(x) for x in bvp.GetPropertyValue("BestViewDirection")]
        valid = int(bvp.GetPropertyValue("ViewValid"))
        simple.Delete(bvp)
        simple.Delete(reader)
        return direction, valid, msgs

    def spacing_runner(row):
        reference, valid, _ = bv_at([1.0, 1.0, 1.0])
        errors, warnings, angles = [], [], []
        for s in (1e-9, 1e-12, 1e9):
            direction, valid_s, msgs = bv_at([s, s, s])
            errors += msgs.errors
            warnings += msgs.warnings
            angles.append(T.angle_deg(direction, reference, unsigned=True) if valid_s else 180.0)
        return Outcome(errors, warnings, [None], {}, False, [], angles=angles,
                       reference_valid=valid)

    def zero_runner(row):
        return run_reader(path, "VolPackDenReader", DataSpacing=[0.0, 1.0, 1.0])

    return [
        Row("rdr.den-spacing", "BV", None, runner=spacing_runner,
            check=lambda o: (o.reference_valid == 1 and B.max(o.angles) < 0.5,
                             "spacing 1e-9, 1e-12, 1e9: %s deg from spacing 1" %
                             ["%.3f" % a for a in o.angles])),
        Row("rdr.den-spacing-0", "RDR", None, runner=zero_runner, expect="error",
            words=("brainsmall.den", "spacing 0 along axis 1", "DataSpacing")),
    ]


# ---- the rows --------------------------------------------------------------------------------
BV_N = {"NumberOfInterestPoints": 500}  # blobs has ~1900 positive responses: no "only" warning
REP = {"OpacitySource": "Representation", "NumberOfInterestPoints": 500}
ISO = {"Method": "Isomap", "ReferenceSampleSize": 300, "NumberOfNeighbors": 10,
       "NumberOfLandmarks": 50}
LLE = dict(ISO, Method="LLE")
DR = {"ReferenceSampleSize": 300}
RD = {"SampleSize": 500}


def widgets(values, extra=None):
    props = dict(extra or {})
    props["GaussianWidgets"] = values
    return props


def merge_of(*keys):
    """Runs MergeChannels on the volumes `keys` (the row's source is the first)."""
    def runner(row):
        return run_filter(row, simple.MergeChannels(Input=[source(k) for k in keys]))
    return runner


ROWS = [
    # BestViewpoint ----------------------------------------------------------------------------
    Row("bv.nan-inf", "BV", "blobs-naninf", BV_N, "warning", ("3 voxel(s) hold NaN/Inf",),
        all_of(along(2, 1.0), cond(lambda o: int(o.props["NumberOfNonFiniteVoxels"]) == 3,
                                   "NumberOfNonFiniteVoxels 3"))),
    Row("bv.all-nan", "BV", "nan", {}, "warning", ("holds no finite value",),
        cond(lambda o: not o.valid and o.outputs[0].GetNumberOfPoints() == 0, "no view, no point")),
    Row("bv.constant", "BV", "constant", {}, "warning", ("constant",),
        cond(lambda o: not o.valid and o.best == [0, 0, 0], "ViewValid 0, direction 0")),
    Row("bv.1x1x1", "BV", "1x1x1", {}, "error", ("fewer than two axes",)),
    Row("bv.line", "BV", "line", {}, "error", ("a line or a point has no view",)),
    Row("bv.thin-z", "BV", "thin-z", {"NumberOfInterestPoints": 100}, "warning",
        ("single slice",), along(2, 1e-3)),
    Row("bv.thin-y", "BV", "thin-y", {"NumberOfInterestPoints": 100}, "warning",
        ("single slice",), along(1, 1e-3)),
    Row("bv.spacing-0", "BV", "blobs-spacing-0", BV_N, "error",
        ("spacing", "axis 0", "DataSpacing")),
    Row("bv.spacing-1", "BV", "blobs", BV_N, "ok", (), along(2, 1.0)),
    Row("bv.spacing-neg", "BV", "blobs-spacing-neg", BV_N, "ok", (),
        all_of(same_direction_as("bv.spacing-1"),
               cond(lambda o: o.outputs[0].GetBounds()[1] <= 0 and
                    o.outputs[0].GetBounds()[0] >= -19, "interest points at x in [-19, 0]"))),
    Row("bv.spacing-1e-9", "BV", "blobs-spacing-1e-9", BV_N, "ok", (),
        same_direction_as("bv.spacing-1")),
    Row("bv.spacing-1e-30", "BV", "blobs-spacing-1e-30", BV_N, "ok", (),
        same_direction_as("bv.spacing-1")),
    Row("bv.spacing-1e30", "BV", "blobs-spacing-1e30", BV_N, "ok", (),
        same_direction_as("bv.spacing-1")),
    Row("bv.spacing-1-1-3", "BV", "blobs-spacing-1-1-3", BV_N, "ok", (), along(2, 1.0)),
    Row("bv.spacing-aniso", "BV", "blobs-spacing-aniso", BV_N, "ok", (),
        same_direction_as("bv.spacing-1-1-3")),
    Row("bv.polydata", "BV", "sphere", {}, "error", ("not image data", "resample")),
    Row("bv.channels-ab", "BV", "two-arrays", dict(BV_N, Channels=["a", "b"]), "ok", (),
        along(2, 1.0)),
    Row("bv.no-channel", "BV", "two-arrays", dict(BV_N, Channels=[]), "ok", (),
        same_direction_as("bv.channels-ab", 1e-6)),
    Row("bv.int8-as-float", "BV", "blobs-int8-as-float", BV_N, "ok", (), along(2, 1.0)),
    Row("bv.int8", "BV", "blobs-int8", BV_N, "ok", (), same_direction_as("bv.int8-as-float", 1e-3)),
    Row("bv.uint16-as-float", "BV", "blobs-uint16-as-float", BV_N, "ok", (), along(2, 1.0)),
    Row("bv.uint16", "BV", "blobs-uint16", BV_N, "ok", (),
        same_direction_as("bv.uint16-as-float", 1e-3)),
    Row("bv.int64-as-float", "BV", "blobs-int64-as-float", BV_N, "ok", (), along(2, 1.0)),
    Row("bv.int64", "BV", "blobs-int64", BV_N, "ok", (),
        same_direction_as("bv.int64-as-float", 1e-3)),
    Row("bv.double", "BV", "blobs-double", BV_N, "ok", (), same_direction_as("bv.spacing-1", 1e-3)),
    Row("bv.N-0", "BV", "blobs", {"NumberOfInterestPoints": 0}, "error",
        ("NumberOfInterestPoints", "positive")),
    Row("bv.N-neg", "BV", "blobs", {"NumberOfInterestPoints": -5}, "error",
        ("NumberOfInterestPoints", "positive")),
    Row("bv.N-1", "BV", "blobs", {"NumberOfInterestPoints": 1}, "warning",
        ("at least 3 interest points",),
        all_of(points(1), cond(lambda o: len(o.warnings) == 1, "one warning, not two"))),
    Row("bv.N-huge", "BV", "blobs", {"NumberOfInterestPoints": 1000000}, "warning",
        ("fewer than the 1000000",), along(2, 1.0)),
    Row("bv.sigma-0", "BV", "blobs", {"GaussianSigma": 0.0}, "error", ("GaussianSigma", "1.5")),
    Row("bv.sigma-neg", "BV", "blobs", {"GaussianSigma": -1.0}, "error", ("GaussianSigma", "1.5")),
    Row("bv.3e38", "BV", "blobs-3e38", BV_N, "warning",
        ("Only 1 of 8000 voxels", "alone decide the view", "OpacityFunction")),
    Row("bv.sigma-tiny", "BV", "blobs", {"GaussianSigma": 1e-9}, "warning",
        ("no voxel has a positive Harris response", "GaussianSigma 1e-09"),
        cond(lambda o: not o.valid, "no view")),
    Row("bv.kernel-even", "BV", "blobs", {"KernelWidth": 4}, "error", ("KernelWidth", "odd")),
    Row("bv.kernel-1", "BV", "blobs", {"KernelWidth": 1}, "warning",
        ("no voxel has a positive Harris response", "KernelWidth 1"),
        cond(lambda o: not B.any("constant" in w for w in o.warnings), "not called constant")),
    Row("bv.kernel-big", "BV", "blobs", dict(BV_N, KernelWidth=31), "ok", (),
        same_direction_as("bv.spacing-1", 1.0)),
    Row("bv.harrisk-neg", "BV", "blobs", {"HarrisK": -0.1}, "error", ("HarrisK", ">= 0")),
    Row("bv.harrisk-10", "BV", "blobs", {"HarrisK": 10.0}, "warning",
        ("no voxel has a positive Harris response", "HarrisK 10"),
        cond(lambda o: not o.valid, "no view")),
    Row("bv.widgets-empty", "BV", "coords", widgets([], REP), "warning", ("No Gaussian widgets",),
        cond(lambda o: not o.valid, "no view")),
    Row("bv.widgets-7", "BV", "coords", widgets(W_PLANE[:7], REP), "error",
        ("7 values", "multiple of 8")),
    Row("bv.widgets-sigma0", "BV", "coords", widgets([0.5, 0.5, 0.5, 0, 1, 1, 1, 1], REP),
        "error", ("sigma 0 must be > 0",)),
    Row("bv.widgets-colour", "BV", "coords",
        widgets([3.0 if n % 8 == 4 else v for n, v in enumerate(W_PLANE)], REP), "warning",
        ("clamped",), along(2, 1.0)),
    Row("bv.widgets-nan", "BV", "coords", widgets(W_PLANE[:7] + [float("nan")], REP), "error",
        ("opacity (number 8",)),
    Row("bv.widgets-10000", "BV", "coords", widgets(W_PLANE + FAR * 9995, REP), "ok", (),
        along(2, 1.0)),
    Row("bv.toggle", "BV", "coords", runner=toggle("BV", "coords", "GaussianWidgets",
                                                   [W_PLANE, W_PLANE_X], direction_of, REP),
        check=no_mismatch),

    # MultichannelFeatures ---------------------------------------------------------------------
    Row("mf.nan-inf", "MF", "ramp-naninf", {"FeatureSet": "24D"}, "warning", ("2 voxel(s)", "NaN"),
        n_features(8)),
    Row("mf.constant", "MF", "constant", {"FeatureSet": "24D"}, "warning", ("constant",),
        all_of(n_features(8), cond(lambda o: B.all(v == 0 for v in fetch_values(o, "Features")),
                                   "features 0"),
               cond(lambda o: not B.any("lower BackgroundThreshold" in w for w in o.warnings),
                    "no advice to lower a threshold of 0"))),
    Row("mf.1x1x1", "MF", "1x1x1", {}, "warning", ("constant",), n_features(2)),
    Row("mf.thin", "MF", "thin-z", {"FeatureSet": "24D"}, "warning", ("values.gradZ",),
        n_features(8)),
    Row("mf.spacing-0", "MF", "ramp-spacing-0", {}, "error", ("spacing", "axis 0", "DataSpacing")),
    # One channel: the features run, with the warning that says how to get several.
    Row("mf.spacing-1", "MF", "ramp", {"FeatureSet": "24D"}, "warning", ONE_CHANNEL,
        keep_values("Features")),
    Row("mf.spacing-neg", "MF", "ramp-spacing-neg", {"FeatureSet": "24D"}, "warning",
        ONE_CHANNEL, same_values("Features", "mf.spacing-1")),
    Row("mf.spacing-1e-9", "MF", "ramp-spacing-1e-9", {"FeatureSet": "24D"}, "warning",
        ONE_CHANNEL, same_values("Features", "mf.spacing-1")),
    Row("mf.spacing-1e9", "MF", "ramp-spacing-1e9", {"FeatureSet": "24D"}, "warning",
        ONE_CHANNEL, same_values("Features", "mf.spacing-1")),
    Row("mf.values-1e36", "MF", "ramp-1e36", {"FeatureSet": "24D"}, "warning",
        ("overflow float32", "values.variance", "rescale the channel"), n_features(8)),
    Row("mf.polydata", "MF", "sphere", {}, "error", ("not image data",)),
    Row("mf.channels-ab", "MF", "two-arrays", {"Channels": ["a", "b"]}, "ok", (),
        all_of(n_features(4), keep_values("Features"))),
    Row("mf.no-channel", "MF", "two-arrays", {"Channels": []}, "ok", (),
        same_values("Features", "mf.channels-ab", 0.0)),
    Row("mf.ramp-6D", "MF", "ramp", {}, "warning", ONE_CHANNEL, keep_values("Features")),
    Row("mf.int8", "MF", "ramp-int8", {}, "warning", ONE_CHANNEL,
        same_values("Features", "mf.ramp-6D")),
    Row("mf.uint16", "MF", "ramp-uint16", {}, "warning", ONE_CHANNEL,
        same_values("Features", "mf.ramp-6D")),
    Row("mf.int64", "MF", "ramp-int64", {}, "warning", ONE_CHANNEL,
        same_values("Features", "mf.ramp-6D")),
    Row("mf.double", "MF", "ramp-double", {}, "warning", ONE_CHANNEL,
        same_values("Features", "mf.ramp-6D")),
    Row("mf.toggle", "MF", "ramp", runner=toggle("MF", "ramp", "FeatureSet", ["24D", "6D"],
                                                 rounded_values("Features")),
        expect="warning", words=ONE_CHANNEL, check=no_mismatch),

    # MergeChannels --------------------------------------------------------------------------------
    Row("mc.grids", "MC", "blobs", runner=merge_of("blobs", "ramp"), expect="error",
        words=("not on one grid", "input 2", "10 x 10 x 10", "input 1", "20 x 20 x 20",
               "Resample")),
    Row("mc.same-grid", "MC", "blobs", runner=merge_of("blobs", "blobs-double"),
        check=cond(lambda o: o.outputs[0].GetPointData().GetNumberOfArrays() == 2 and
                   o.outputs[0].GetNumberOfPoints() == 8000, "both arrays on the 20^3 grid")),

    # DimensionReduction --------------------------------------------------------------------------
    Row("dr.ref-0", "DR", "features", {"ReferenceSampleSize": 0}, "error",
        ("ReferenceSampleSize", "positive")),
    Row("dr.ref-1", "DR", "features", {"ReferenceSampleSize": 1}, "error",
        ("ReferenceSampleSize (1)", "raise")),
    Row("dr.ref-2", "DR", "features", {"ReferenceSampleSize": 2}, "error",
        ("ReferenceSampleSize (2)", "raise")),
    Row("dr.ref-huge", "DR", "features", {"ReferenceSampleSize": 1000000}, "warning",
        ("exceeds the number of voxels",), coordinates_ok(3)),
    Row("dr.k-0", "DR", "features", dict(ISO, NumberOfNeighbors=0), "error",
        ("NumberOfNeighbors", "positive")),
    Row("dr.k-1-isomap", "DR", "features", dict(ISO, NumberOfNeighbors=1), "warning",
        ("connected components", "larger NumberOfNeighbors"), coordinates_ok(3)),
    Row("dr.k-1-lle", "DR", "features", dict(LLE, NumberOfNeighbors=1), "warning",
        ("connected components",), coordinates_ok(3)),
    Row("dr.k-ge-M", "DR", "features", dict(ISO, NumberOfNeighbors=50, ReferenceSampleSize=40),
        "error", ("NumberOfNeighbors (50)", "lower it")),
    Row("dr.L-0", "DR", "features", dict(ISO, NumberOfLandmarks=0), "error",
        ("NumberOfLandmarks", "positive")),
    Row("dr.L-1-isomap", "DR", "features", dict(ISO, NumberOfLandmarks=1), "warning",
        ("1 landmarks asked for, 4 used",), coordinates_ok(3)),
    Row("dr.L-1-lle", "DR", "features", dict(LLE, NumberOfLandmarks=1), "warning",
        ("1 landmarks asked for, 15 used",), coordinates_ok(3)),
    Row("dr.L-above", "DR", "features", dict(ISO, NumberOfLandmarks=5000), "warning",
        ("5000 landmarks asked for, 300 used",), coordinates_ok(3)),
    Row("dr.L-above-lle", "DR", "features", dict(LLE, NumberOfLandmarks=5000), "ok", (),
        coordinates_ok(3)),
    Row("dr.dim-0", "DR", "features", dict(DR, OutputDimension=0), "error",
        ("OutputDimension", "2 or 3")),
    Row("dr.dim-1", "DR", "features", dict(DR, OutputDimension=1), "error",
        ("OutputDimension", "2 or 3")),
    Row("dr.dim-2", "DR", "features", dict(DR, OutputDimension=2), "ok", (),
        all_of(coordinates_ok(2), cond(lambda o: [
            o.array("ReducedCoordinates").GetComponentName(c) for c in range(2)] ==
            ["dim1", "dim2"], "components dim1, dim2"))),
    Row("dr.dim-10", "DR", "features", dict(DR, OutputDimension=10), "error",
        ("OutputDimension", "2 or 3")),
    Row("dr.nan", "DR", "features-nan", DR, "error", ("non-finite", "voxel 5")),
    Row("dr.constant", "DR", "features-constant", DR, "error",
        ("0 of the 4 feature components vary",)),
    Row("dr.1x1x1", "DR", "features-1x1x1", DR, "error", ("vary",)),
    Row("dr.no-feature", "DR", "features-none",
        dict(DR, FeatureSet="Use input array", Features=["POINTS", ""]), "error",
        ("No feature array selected", "Features property")),
    Row("dr.no-feature-auto", "DR", "features-none", DR, "warning",
        ("values_0.gradZ", "constant"), coordinates_ok(3)),
    Row("dr.polydata", "DR", "sphere", {}, "error", ("not image data",)),
    Row("dr.int64", "DR", "features-int64", DR, "ok", (), coordinates_ok(3)),
    Row("dr.int8", "DR", "features-int8", DR, "ok", (), coordinates_ok(3)),
    Row("dr.toggle", "DR", "features", runner=toggle("DR", "features", "Method",
                                                     ["Isomap", "PCA"],
                                                     rounded_values("ReducedCoordinates"), ISO),
        check=no_mismatch),

    # ReducedDomain -------------------------------------------------------------------------------
    Row("rd.nan-coords", "RD", "coords-nan", widgets(W_PLANE, {"SampleSize": 100000}), "warning",
        ("768 point(s)", "NaN"), points(3328)),
    Row("rd.all-nan", "RD", "coords-allnan", widgets(W_PLANE), "error", ("No point has finite",)),
    Row("rd.constant-seed", "RD", "coords-constant", {"SeedWidgetCount": 2}, "warning",
        ("1 distinct", "SkipLargestCluster"),
        all_of(points(512), cond(lambda o: len(o.props["SeededWidgets"]) == 0,
                                 "no seeded widget"))),
    Row("rd.1x1x1", "RD", "coords-1x1x1", {"SeedWidgetCount": 1, "SkipLargestCluster": 0}, "ok",
        (), all_of(points(1), cond(lambda o: len(o.props["SeededWidgets"]) == 8,
                                   "1 seeded widget"))),
    Row("rd.1-component", "RD", "coords-1comp", {}, "error", ("1 component(s)", "2 or 3")),
    Row("rd.polydata", "RD", "sphere", {"Coordinates": ["POINTS", "ReducedCoordinates"]}, "error",
        ("no coordinates array", "DimensionReduction")),
    Row("rd.polydata-coords", "RD", "sphere-coords", widgets(W_PLANE, RD), "ok", (),
        points(50)),
    Row("rd.widgets-empty", "RD", "coords", widgets([], RD), "warning", ("No Gaussian widgets",),
        cond(lambda o: o.array("RGBA").GetRange(3) == (0.0, 0.0), "RGBA opacity 0")),
    Row("rd.widgets-7", "RD", "coords", widgets(W_PLANE[:7], RD), "error", ("multiple of 8",)),
    Row("rd.widgets-sigma0", "RD", "coords", widgets([0.5, 0.5, 0.5, -0.1, 1, 1, 1, 1], RD),
        "error", ("must be > 0",)),
    Row("rd.widgets-colour", "RD", "coords",
        widgets([-3.0 if n % 8 == 4 else v for n, v in enumerate(W_PLANE)], RD), "warning",
        ("clamped",), rgba_range),
    Row("rd.widgets-nan", "RD", "coords", widgets(W_PLANE[:7] + [float("nan")], RD), "error",
        ("opacity (number 8",)),
    Row("rd.widgets-plane", "RD", "coords", widgets(W_PLANE, RD), "ok", (), keep_values("RGBA")),
    Row("rd.widgets-10000", "RD", "coords", widgets(W_PLANE + FAR * 9995, RD), "ok", (),
        same_values("RGBA", "rd.widgets-plane", 0.0)),
    Row("rd.toggle", "RD", "coords", runner=toggle("RD", "coords", "GaussianWidgets",
                                                   [RED, GREEN], rounded_values("RGBA"), RD),
        check=no_mismatch),

    # The Gaussian TF Volume representation -------------------------------------------------------
    Row("tf.nan-coords", "TF", "coords-nan", {}, "ok", (),
        all_of(drawn, pixel_is("red", 0), cond(lambda o: B.max(o.pixel["nan-side"]) <= 10,
                                               "NaN voxels transparent"))),
    Row("tf.constant", "TF", "coords-constant", {}, "ok", (), all_of(drawn, pixel_is("centre", 0))),
    Row("tf.1x1x1", "TF", "coords-1x1x1", {}, "ok", (),
        cond(lambda o: o.props["valid"] == 1, "valid")),
    Row("tf.thin", "TF", "coords-thin", {}, "ok", (), drawn),
    Row("tf.spacing-0", "TF", "coords-spacing-0", {}, "error",
        ("spacing", "axis 0", "Nothing is drawn")),
    Row("tf.spacing-neg", "TF", "coords-spacing-neg", {}, "error",
        ("negative spacing", "Resample To Image")),
    Row("tf.spacing-1", "TF", "coords", FAINT, "ok", (), all_of(drawn, keep_pixels)),
    Row("tf.spacing-1e-9", "TF", "coords-spacing-1e-9", FAINT, "ok", (),
        same_pixels("tf.spacing-1")),
    Row("tf.spacing-1e9", "TF", "coords-spacing-1e9", FAINT, "ok", (), same_pixels("tf.spacing-1")),
    Row("tf.spacing-1-v", "TF", "coords", dict(FAINT, Classification="Per voxel"), "ok", (),
        all_of(drawn, keep_pixels)),
    Row("tf.spacing-1e-9-v", "TF", "coords-spacing-1e-9", dict(FAINT, Classification="Per voxel"),
        "ok", (), same_pixels("tf.spacing-1-v")),
    Row("tf.spacing-1e9-v", "TF", "coords-spacing-1e9", dict(FAINT, Classification="Per voxel"),
        "ok", (), same_pixels("tf.spacing-1-v")),
    Row("tf.int16", "TF", "coords-int16", {"GaussianWidgets": [25, 50, 50, 15, 1, 0, 0, 1]}, "ok",
        (), all_of(drawn, pixel_is("red", 0))),
    Row("tf.widgets-empty", "TF", "coords", {"GaussianWidgets": []}, "warning", ("transparent",),
        cond(lambda o: o.shot.max_channel() <= 10, "nothing drawn"),
        before={"GaussianWidgets": RED}),
    Row("tf.widgets-7", "TF", "coords", {"GaussianWidgets": RED[:7]}, "error", ("multiple of 8",)),
    Row("tf.widgets-sigma0", "TF", "coords", {"GaussianWidgets": [0.25, 0.5, 0.5, 0, 1, 0, 0, 1]},
        "error", ("must be > 0",)),
    Row("tf.widgets-sigma-", "TF", "coords",
        {"GaussianWidgets": RED + [0.75, 0.5, 0.5, -1, 0, 1, 0, 1]},
        "error", ("must be > 0",)),
    Row("tf.widgets-colour", "TF", "coords",
        {"GaussianWidgets": [0.25, 0.5, 0.5, 0.15, 3, -1, 0, 7]},
        "warning", ("clamped",), all_of(drawn, pixel_is("red", 0))),
    Row("tf.widgets-nan", "TF", "coords", {"GaussianWidgets": RED[:7] + [float("nan")]}, "error",
        ("opacity (number 8",)),
    Row("tf.widgets-10000", "TF", "coords", {"GaussianWidgets": RED + GREEN + FAR * 9998}, "error",
        ("at most 64", "Per voxel")),
    Row("tf.widgets-10000-v", "TF", "coords", {"GaussianWidgets": RED + GREEN + FAR * 9998,
                                              "Classification": "Per voxel"}, "ok", (),
        all_of(drawn, pixel_is("red", 0), pixel_is("green", 1))),
    Row("tf.toggle", "TF", "coords", runner=toggle_tf(), check=no_mismatch),
    Row("tf.polydata", "TF", "sphere", runner=offered_for,
        check=lambda o: (not o.offered, "not among a Sphere's representations %s" % o.available)),
] + nifti_rows() + den_rows()

# Expected outcomes that another change of the suite delivers: listed, not asserted.
PENDING = [
    ("pending.overflow", "MF", "ramp at spacing 1e-30 (squared gradients overflow float32)",
     "the features of spacing 1 (today the overflow warning, gradMag 0)"),
    ("pending.underflow", "MF", "ramp at spacing 1e30 (squared gradients underflow float32)",
     "the features of spacing 1 (today gradMag is 0 and called a constant column)"),
]


# ---- run the table -------------------------------------------------------------------------------
def check_row(row, o):
    label = "%s (%s)" % (row.id, row.to)
    words = list(row.words)
    print("%s: errors %s warnings %s" % (label, [e.split("): ", 1)[-1].strip() for e in o.errors],
                                         [w.split("): ", 1)[-1].strip() for w in o.warnings]))
    C.check(not o.non_finite, "%s: no NaN/Inf in an output array %s" % (label, o.non_finite))
    if row.expect == "error":
        found = B.any(B.all(w.lower() in e.lower() for w in words) for e in o.errors)
        C.check(found, "%s: error mentioning %s" % (label, words))
        if row.to in CLASSES:
            C.check(B.any(CLASSES[row.to] in e for e in o.errors),
                    "%s: the error names the filter (%s)" % (label, CLASSES[row.to]))
        C.check(o.empty, "%s: empty output, nothing drawn" % label)
    else:
        C.check(not o.errors, "%s: no error" % label)
        if row.expect == "warning":
            found = B.any(B.all(w.lower() in x.lower() for w in words) for x in o.warnings)
            C.check(found, "%s: warning mentioning %s" % (label, words))
        else:
            C.check(not o.warnings, "%s: no warning" % label)
    if row.check:
        ok, text = row.check(o)
        C.check(ok, "%s: %s" % (label, text))


ids = [row.id for row in ROWS]
C.check(len(set(ids)) == len(ids), "row ids are unique")
C.check(len(ROWS) >= 30, "%d rows (at least 30)" % len(ROWS))
documented = [line.split("|")[0].strip() for line in __doc__.splitlines() if "|" in line]
# Rows that only give a baseline for others need no line of their own.
BASELINES = ("bv.spacing-1", "bv.spacing-1-1-3", "bv.channels-ab", "bv.int8-as-float",
             "bv.uint16-as-float", "bv.int64-as-float", "mf.spacing-1", "mf.channels-ab",
             "mf.ramp-6D", "rd.widgets-plane", "tf.spacing-1", "tf.spacing-1-v")
undocumented = [i for i in ids if i not in documented and i not in BASELINES]
C.check(not undocumented, "every row is in the table at the top %s" % undocumented)
for row in ROWS:
    outcome = (row.runner or (run_tf if row.to == "TF" else run_filter))(row)
    RESULTS[row.id] = outcome
    check_row(row, outcome)
    proxy = getattr(outcome, "proxy", None)
    if proxy is not None and row.runner is None:
        simple.Delete(proxy)
        outcome.proxy = None
for pending in PENDING:
    print("PENDING (not asserted) %s (%s): %s -> %s" % pending)
C.finish()
