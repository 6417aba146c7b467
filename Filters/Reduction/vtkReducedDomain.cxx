#include "vtkReducedDomain.h"

#include "vtkCellArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"

// The VTK-free core (Filters/Core).
#include "GaussianTransferFunction.h"
#include "SeededRandom.h" // uniformIndex: the suite's portable seeded RNG
#include "WidgetSeeding.h"

#include "../Common/mcvCoordinateArrays.h" // float32 or float16 coordinates
#include "../Common/mcvInternalArrays.h"   // vtkGhostType, vtkValidPointMask
#include "../Common/mcvPrintMembers.h"
#include "../Common/mcvVoxelCloud.h"       // vertices, copied tuples, VoxelId

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkReducedDomain);

struct vtkReducedDomain::vtkInternals
{
  vtkNew<vtkDoubleArray> SeededWidgets;
  vtkNew<vtkDoubleArray> SeededWidgetDetails;
};

namespace
{

// Knuth's selection sampling (Algorithm S): exactly `wanted` of the `eligible` points,
// uniformly, in one ordered pass and O(wanted) memory (a volume can have 10^8 voxels).
std::vector<vtkIdType> selectionSample(const std::vector<bool>& isEligible, std::size_t eligible,
  std::size_t wanted, std::uint64_t seed)
{
  std::vector<vtkIdType> picked;
  picked.reserve(std::min(wanted, eligible));
  std::uint64_t state = seed * 0x9E3779B97F4A7C15ull + 0x5851F42D4C957F2Dull;
  std::size_t seen = 0;
  for (std::size_t i = 0; i < isEligible.size() && picked.size() < wanted; ++i)
  {
    if (!isEligible[i])
    {
      continue;
    }
    const std::size_t remaining = eligible - seen++;
    if (wanted >= eligible || mcv::uniformIndex(state, remaining) < wanted - picked.size())
    {
      picked.push_back(static_cast<vtkIdType>(i));
    }
  }
  return picked;
}

// The input's Foreground mask (uint8, 1 = foreground, one per point of `n`), or nullptr
// when there is none, it is not such an array, or it marks no point (then the mask would
// leave nothing to show; the caller warns).
vtkUnsignedCharArray* foregroundMask(vtkPointData* pd, vtkIdType n, bool& marksNothing)
{
  marksNothing = false;
  auto* mask = vtkUnsignedCharArray::SafeDownCast(pd->GetAbstractArray("Foreground"));
  if (!mask || mask->GetNumberOfComponents() != 1 || mask->GetNumberOfTuples() != n)
  {
    return nullptr;
  }
  const unsigned char* m = mask->GetPointer(0);
  marksNothing = std::none_of(m, m + n, [](unsigned char v) { return v != 0; });
  return marksNothing ? nullptr : mask;
}

vtkSmartPointer<vtkPolyData> widgetGlyphSource(const std::vector<mcv::GaussianWidget>& widgets)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> verts;
  auto makeArray = [](const char* name, int components) {
    auto a = vtkSmartPointer<vtkFloatArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(components);
    return a;
  };
  auto sigma = makeArray("Sigma", 1), diameter = makeArray("Diameter", 1);
  auto opacity = makeArray("Opacity", 1), color = makeArray("Color", 3);
  vtkNew<vtkIntArray> index;
  index->SetName("WidgetIndex");
  for (std::size_t i = 0; i < widgets.size(); ++i)
  {
    const mcv::GaussianWidget& w = widgets[i];
    verts->InsertNextCell(1);
    verts->InsertCellPoint(points->InsertNextPoint(w.center));
    sigma->InsertNextValue(static_cast<float>(w.sigma));
    // a hidden widget (peak opacity 0) selects nothing: its sphere glyph is not drawn
    diameter->InsertNextValue(w.opacity > 0 ? static_cast<float>(2 * w.sigma) : 0.0f);
    opacity->InsertNextValue(static_cast<float>(w.opacity));
    color->InsertNextTuple(w.color);
    index->InsertNextValue(static_cast<int>(i));
  }
  poly->SetPoints(points);
  poly->SetVerts(verts);
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(sigma), static_cast<vtkDataArray*>(diameter),
         static_cast<vtkDataArray*>(opacity), static_cast<vtkDataArray*>(color),
         static_cast<vtkDataArray*>(index) })
  {
    poly->GetPointData()->AddArray(a);
  }
  poly->GetPointData()->SetScalars(color);
  return poly;
}


// The distinct rows of `packed` (rows of `dims` floats), how many rows each stands for,
// and the distinct row of every row.
struct DistinctRows
{
  std::vector<float> rows;
  std::vector<double> multiplicity;
  std::vector<vtkIdType> of;
};

DistinctRows distinctRows(const std::vector<float>& packed, int dims)
{
  // Sort row indices lexicographically, keep the first of each run.
  const std::size_t m = packed.size() / static_cast<std::size_t>(dims);
  DistinctRows d;
  d.of.resize(m);
  std::vector<std::size_t> order(m);
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    order[i] = i;
  }
  auto row = [&packed, dims](std::size_t i) { return packed.data() + i * dims; };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::lexicographical_compare(row(a), row(a) + dims, row(b), row(b) + dims);
  });
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    if (i == 0 || !std::equal(row(order[i]), row(order[i]) + dims, row(order[i - 1])))
    {
      d.rows.insert(d.rows.end(), row(order[i]), row(order[i]) + dims);
      d.multiplicity.push_back(0.0);
    }
    d.multiplicity.back() += 1.0;
    d.of[order[i]] = static_cast<vtkIdType>(d.multiplicity.size() - 1);
  }
  return d;
}

// WidgetOpacity, RGBA (bytes) and DisplayColor of `m` points from their RGBA floats and
// how strongly the shown widgets select each (`selection`, m values in [0, 1]).
// DisplayColor: the widget colour over light grey by that selection, so points no widget
// selects stay visible (the domain is where the user looks for the next structure).
void addColourArrays(
  const std::vector<float>& rgbaFloat, const std::vector<float>& selection, vtkIdType m, vtkPointData* outPD)
{
  vtkNew<vtkUnsignedCharArray> rgba;
  rgba->SetName("RGBA");
  rgba->SetNumberOfComponents(4);
  rgba->SetNumberOfTuples(m);
  vtkNew<vtkFloatArray> opacity;
  opacity->SetName("WidgetOpacity");
  opacity->SetNumberOfTuples(m);
  vtkNew<vtkUnsignedCharArray> displayColor;
  displayColor->SetName("DisplayColor");
  displayColor->SetNumberOfComponents(3);
  displayColor->SetNumberOfTuples(m);
  const float grey = 0.75f;
  auto toByte = [](float v) { return static_cast<unsigned char>(std::lround(std::min(1.f, std::max(0.f, v)) * 255.f)); };
  for (vtkIdType s = 0; s < m; ++s)
  {
    const float* c = rgbaFloat.data() + 4 * s;
    const float blend = selection[static_cast<std::size_t>(s)];
    for (int k = 0; k < 4; ++k)
    {
      rgba->SetTypedComponent(s, k, toByte(c[k]));
    }
    for (int k = 0; k < 3; ++k)
    {
      displayColor->SetTypedComponent(s, k, toByte(blend * c[k] + (1.f - blend) * grey));
    }
    opacity->SetValue(s, c[3]);
  }
  outPD->AddArray(opacity);
  outPD->AddArray(rgba);
  outPD->AddArray(displayColor);
  outPD->SetScalars(displayColor);
}

// The widgets with every shown one (peak opacity > 0) at peak opacity 1: the opacity they
// give a point is how strongly the shown widgets select it, whatever their peak opacities.
// The domain colours points by that, not by the opacity: a widget of low peak opacity that
// selects many voxels dominates the volume all the same (its samples add up along each
// ray), so its points should stand out as clearly as those of a sparse, opaque widget.
std::vector<mcv::GaussianWidget> selectingWidgets(const std::vector<mcv::GaussianWidget>& widgets)
{
  std::vector<mcv::GaussianWidget> selecting = widgets;
  for (mcv::GaussianWidget& w : selecting)
  {
    w.opacity = w.opacity > 0 ? 1.0 : 0.0;
  }
  return selecting;
}

// FocusBounds (field data, one 6-component tuple xmin, xmax, ymin, ymax, zmin, zmax): per
// axis the sampled points without the far outliers, widened to hold each shown widget's
// sphere (centre +- sigma). show_dual_domain frames the domain view on it: a few far
// outliers (ParaView's Reset Camera fits them all) would shrink the dense cloud, where the
// structures are, to a corner of the view. An outlier is a point cut off from the rest by
// an empty gap: from the 5th and 95th percentiles the bounds grow outwards through the
// sorted values as long as no gap between two of them exceeds 5 % of that central range,
// so continuous arms and sparse fringes stay in view and only isolated points drop out.
vtkSmartPointer<vtkDoubleArray> focusBounds(
  const std::vector<float>& xyz, vtkIdType m, int dims, const std::vector<mcv::GaussianWidget>& widgets)
{
  double bounds[6] = { 0, 0, 0, 0, 0, 0 };
  std::vector<float> axis(static_cast<std::size_t>(m));
  const std::size_t last = axis.size() - 1;
  for (int a = 0; a < 3; ++a)
  {
    for (std::size_t i = 0; i < axis.size(); ++i)
    {
      axis[i] = xyz[3 * i + a];
    }
    std::sort(axis.begin(), axis.end());
    std::size_t low = static_cast<std::size_t>(std::floor(0.05 * static_cast<double>(last)));
    std::size_t high = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(last)));
    const double gap = 0.05 * (static_cast<double>(axis[high]) - axis[low]);
    while (low > 0 && axis[low] - axis[low - 1] <= gap)
    {
      --low;
    }
    while (high < last && axis[high + 1] - axis[high] <= gap)
    {
      ++high;
    }
    bounds[2 * a] = axis[low];
    bounds[2 * a + 1] = axis[high];
  }
  for (const mcv::GaussianWidget& w : widgets)
  {
    if (!(w.opacity > 0))
    {
      continue;
    }
    for (int a = 0; a < dims; ++a) // 2D: the sphere sits at z = 0 with the points
    {
      bounds[2 * a] = std::min(bounds[2 * a], w.center[a] - w.sigma);
      bounds[2 * a + 1] = std::max(bounds[2 * a + 1], w.center[a] + w.sigma);
    }
  }
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName("FocusBounds");
  array->SetNumberOfComponents(6);
  array->InsertNextTuple(bounds);
  return array;
}

} // namespace

//------------------------------------------------------------------------------
vtkReducedDomain::vtkReducedDomain()
  : Internals(new vtkInternals)
{
  this->SetNumberOfOutputPorts(2);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "ReducedCoordinates");
  this->Internals->SeededWidgets->SetName("SeededWidgets");
  this->Internals->SeededWidgetDetails->SetName("SeededWidgetDetails");
}

//------------------------------------------------------------------------------
vtkReducedDomain::~vtkReducedDomain() = default;

//------------------------------------------------------------------------------
void vtkReducedDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  mcvPrintMembersMacro(os, indent, this->SampleSize, this->RandomSeed, this->SeedWidgetCount,
    this->SeedWidgetOpacity, this->SkipLargestCluster);
}

//------------------------------------------------------------------------------
vtkDoubleArray* vtkReducedDomain::GetSeededWidgets()
{
  return this->Internals->SeededWidgets;
}

//------------------------------------------------------------------------------
vtkDoubleArray* vtkReducedDomain::GetSeededWidgetDetails()
{
  return this->Internals->SeededWidgetDetails;
}

//------------------------------------------------------------------------------
double vtkReducedDomain::ForegroundRayLength(vtkDataSet* input, double foregroundPoints)
{
  auto* image = vtkImageData::SafeDownCast(input);
  if (!image || foregroundPoints < 1 || image->GetNumberOfCells() < 1)
  {
    return 0; // no grid to measure a ray on: the fixed opacities (and veil) of the core
  }
  double spacing[3];
  image->GetSpacing(spacing);
  const double voxel = std::cbrt(std::abs(spacing[0] * spacing[1] * spacing[2]));
  double bounds[6];
  image->GetBounds(bounds);
  const double diagonal = std::sqrt(std::pow(bounds[1] - bounds[0], 2) +
    std::pow(bounds[3] - bounds[2], 2) + std::pow(bounds[5] - bounds[4], 2));
  // ParaView's default Scalar Opacity Unit Distance (vtkSMBoundsDomain's
  // approximate_cell_length): the diagonal over the cube root of the number of cells.
  const double unit = diagonal / std::cbrt(static_cast<double>(image->GetNumberOfCells()));
  if (!(voxel > 0) || !(unit > 0) || !std::isfinite(voxel) || !std::isfinite(unit))
  {
    return 0;
  }
  // Mean chord of a ball of the foreground's volume (Cauchy: 4 V / S = 4/3 r), in voxels.
  const double radius = std::cbrt(3.0 * foregroundPoints / (4.0 * 3.14159265358979323846));
  return (4.0 / 3.0) * radius * voxel / unit;
}

//------------------------------------------------------------------------------
// What one execution samples: the coordinates, the points that may be drawn and the sample.
struct vtkReducedDomain::Sample
{
  vtkDataArray* coordinates = nullptr;
  int dims = 0;
  vtkIdType n = 0;
  vtkUnsignedCharArray* foreground = nullptr;
  std::vector<bool> eligible;
  std::size_t eligibleCount = 0;
  std::vector<vtkIdType> ids; // the sampled points
  vtkIdType m = 0;
  std::vector<float> xyz;    // m x 3 (z = 0 for 2D)
  std::vector<float> packed; // m x dims
};

//------------------------------------------------------------------------------
int vtkReducedDomain::RequestMultichannelData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->Internals->SeededWidgets->Reset();
  this->Internals->SeededWidgetDetails->Reset();
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0], 0);
  vtkPolyData* domain = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* widgetOutput = vtkPolyData::GetData(outputVector, 1);
  if (!input || !domain || !widgetOutput)
  {
    vtkErrorMacro("ReducedDomain needs a dataset input.");
    return 0;
  }
  // Every process holds the whole volume and would draw the same sample: asked for
  // pieces (mpiexec pvbatch, an MPI pvserver, streaming), piece 0 outputs the sample and
  // the widgets and the other pieces stay empty, so the gathered domain holds each sampled
  // voxel once, the points of a one-process run.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) &&
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) > 0)
  {
    domain->Initialize();
    widgetOutput->Initialize();
    return 1;
  }

  // ---- Coordinates and widgets -------------------------------------------------------
  Sample sample;
  sample.coordinates = this->FindCoordinates(inputVector, input);
  if (!sample.coordinates)
  {
    return 0;
  }
  sample.dims = sample.coordinates->GetNumberOfComponents();
  sample.n = sample.coordinates->GetNumberOfTuples();
  const mcv::WidgetList widgets = this->ParseGaussianWidgets();
  if (!widgets.ok())
  {
    vtkErrorMacro(<< widgets.error);
    return 0;
  }
  if (this->SeedWidgetCount == 0) // seeding runs with no widgets yet: nothing to warn about
  {
    this->ReportWarnings(widgets.warnings);
  }
  if (!this->DrawSample(input, sample))
  {
    return 0;
  }
  if (!this->WriteDomain(input, sample, widgets, domain))
  {
    return 0;
  }
  this->UpdateProgress(0.7);

  std::vector<mcv::GaussianWidget> shown = widgets.widgets;
  if (this->SeedWidgetCount > 0 && !this->SeedWidgets(sample, widgets, domain->GetPointData(), shown))
  {
    domain->Initialize(); // an error leaves no output behind
    widgetOutput->Initialize();
    this->Internals->SeededWidgets->Reset();
    this->Internals->SeededWidgetDetails->Reset();
    return 0;
  }

  // ---- Widgets output -------------------------------------------------------------------------
  domain->GetFieldData()->AddArray(focusBounds(sample.xyz, sample.m, sample.dims, shown));
  widgetOutput->ShallowCopy(widgetGlyphSource(shown));
  this->UpdateProgress(1.0);
  return 1;
}

// The coordinates array (2 or 3 components); nullptr after an error (reported).
vtkDataArray* vtkReducedDomain::FindCoordinates(vtkInformationVector** inputVector, vtkDataSet* input)
{
  vtkDataArray* coordinates = this->GetInputArrayToProcess(0, inputVector);
  if (!coordinates)
  {
    // ParaView can leave the selection at a placeholder ("0") when the filter is made
    // before its input has executed: fall back to the documented default.
    coordinates = input->GetPointData()->GetArray("ReducedCoordinates");
  }
  if (!coordinates)
  {
    vtkErrorMacro("The input has no coordinates array (default ReducedCoordinates): apply "
                  "DimensionReduction first, or choose the array in Coordinates.");
    return nullptr;
  }
  const int dims = coordinates->GetNumberOfComponents();
  if (dims != 2 && dims != 3)
  {
    vtkErrorMacro("The coordinates array '" << (coordinates->GetName() ? coordinates->GetName() : "")
      << "' has " << dims << " component(s); the reduced domain needs 2 or 3.");
    return nullptr;
  }
  return coordinates;
}

// ---- The sample: foreground points with finite coordinates --------------------------
bool vtkReducedDomain::DrawSample(vtkDataSet* input, Sample& s)
{
  if (!this->MarkEligible(input, s))
  {
    return false;
  }
  this->UpdateProgress(0.2);
  // Settings that cannot be honoured are errors, not silent changes.
  if (this->SampleSize < 1)
  {
    vtkErrorMacro("SampleSize must be at least 1 (got " << this->SampleSize << ").");
    return false;
  }
  if (this->SeedWidgetCount < 0 || this->SeedWidgetCount > 64)
  {
    vtkErrorMacro("SeedWidgetCount must be between 0 and 64 (got " << this->SeedWidgetCount
                                                                  << ").");
    return false;
  }
  if (std::isnan(this->SeedWidgetOpacity))
  {
    vtkErrorMacro("SeedWidgetOpacity is NaN: give a peak opacity in [0, 1].");
    return false;
  }
  this->LastForegroundRayLength = ForegroundRayLength(input, static_cast<double>(s.eligibleCount));
  s.ids = selectionSample(s.eligible, s.eligibleCount, static_cast<std::size_t>(this->SampleSize),
    static_cast<std::uint64_t>(this->RandomSeed));
  s.m = static_cast<vtkIdType>(s.ids.size());
  s.xyz.assign(static_cast<std::size_t>(s.m) * 3, 0.0f);
  s.packed.resize(static_cast<std::size_t>(s.m) * s.dims);
  for (vtkIdType i = 0; i < s.m; ++i)
  {
    for (int c = 0; c < s.dims; ++c)
    {
      const float v = static_cast<float>(mcv::vtkhelpers::coordinateComponent(s.coordinates, s.ids[i], c));
      s.xyz[3 * i + c] = v;
      s.packed[s.dims * i + c] = v;
    }
  }
  return true;
}

// The points that may be drawn: in the foreground (when the input has a Foreground mask)
// with finite coordinates; false when there is none (an error).
bool vtkReducedDomain::MarkEligible(vtkDataSet* input, Sample& s)
{
  bool maskMarksNothing = false;
  s.foreground = foregroundMask(input->GetPointData(), s.n, maskMarksNothing);
  if (maskMarksNothing)
  {
    this->ReportWarnings({ "The Foreground array marks no voxel (every voxel is background): "
                           "the domain shows all of them." });
  }
  s.eligible.assign(static_cast<std::size_t>(s.n), false);
  std::size_t nonFinite = 0; // foreground points left out for NaN/Inf coordinates
  for (vtkIdType i = 0; i < s.n; ++i)
  {
    bool ok = !s.foreground || s.foreground->GetValue(i) != 0;
    const bool considered = ok;
    for (int c = 0; c < s.dims && ok; ++c)
    {
      ok = std::isfinite(mcv::vtkhelpers::coordinateComponent(s.coordinates, i, c));
    }
    s.eligible[static_cast<std::size_t>(i)] = ok;
    s.eligibleCount += ok ? 1 : 0;
    nonFinite += considered && !ok ? 1 : 0;
  }
  if (s.eligibleCount == 0)
  {
    vtkErrorMacro(<< (s.foreground ? "No foreground point" : "No point") << " has finite reduced coordinates.");
    return false;
  }
  if (nonFinite > 0)
  {
    // Holes in the domain are said, as BestViewpoint says them for the volume.
    vtkWarningMacro(<< nonFinite << " point(s) have NaN/Inf in the coordinates '"
                    << (s.coordinates->GetName() ? s.coordinates->GetName() : "")
                    << "': they are left out of the domain (and drawn transparent in the volume).");
  }
  return true;
}

// ---- Domain output: the sampled points, the input's arrays there, their colours -----------
bool vtkReducedDomain::WriteDomain(
  vtkDataSet* input, const Sample& s, const mcv::WidgetList& widgets, vtkPolyData* domain)
{
  // Colour of every sampled point through the widgets.
  std::vector<float> rgbaFloat(static_cast<std::size_t>(s.m) * 4);
  const mcv::CoordinateView view{ s.packed.data(), static_cast<std::size_t>(s.m), s.dims };
  const mcv::TransferFunctionRun run =
    mcv::applyGaussianWidgets(view, widgets.widgets, rgbaFloat.data(), mcv::Device::CPU);
  std::vector<float> selection(static_cast<std::size_t>(s.m));
  const mcv::TransferFunctionRun selectionRun = mcv::gaussianWidgetOpacity(
    view, selectingWidgets(widgets.widgets), selection.data(), mcv::Device::CPU);
  if (!run.ok() || !selectionRun.ok())
  {
    vtkErrorMacro(<< (run.ok() ? selectionRun.error : run.error));
    return false;
  }
  this->UpdateProgress(0.5);

  vtkNew<vtkFloatArray> pointArray;
  pointArray->SetNumberOfComponents(3);
  pointArray->SetNumberOfTuples(s.m);
  std::copy(s.xyz.begin(), s.xyz.end(), pointArray->GetPointer(0));
  vtkNew<vtkPoints> points;
  points->SetData(pointArray);
  domain->SetPoints(points);
  mcv::vtkhelpers::addVertexPerPoint(domain, s.m);

  // The input's arrays without the coordinates/features, at the sampled points.
  vtkPointData* outPD = domain->GetPointData();
  mcv::vtkhelpers::copyPointTuples(input->GetPointData(), s.ids, outPD,
    [&s](vtkAbstractArray* source) {
      return source == s.coordinates || std::string(source->GetName()) == "Features";
    });
  mcv::vtkhelpers::addVoxelIds(outPD, s.ids);
  addColourArrays(rgbaFloat, selection, s.m, outPD);
  return true;
}

// ---- Seeded widgets (k-means of the distinct sampled coordinates) ---------------------
bool vtkReducedDomain::SeedWidgets(
  const Sample& s, const mcv::WidgetList& widgets, vtkPointData* outPD, std::vector<mcv::GaussianWidget>& shown)
{
  mcv::WidgetSeedingOptions options;
  options.count = this->SeedWidgetCount;
  options.seed = static_cast<std::uint64_t>(this->RandomSeed);
  options.opacity = std::min(1.0, std::max(0.0, this->SeedWidgetOpacity));
  if (options.opacity != this->SeedWidgetOpacity)
  {
    vtkWarningMacro("SeedWidgetOpacity " << this->SeedWidgetOpacity
                                         << " is outside [0, 1]: the widgets are seeded with "
                                         << options.opacity << ".");
  }
  // The largest cluster stands for the background only when nothing else removed it.
  options.skipLargest = this->SkipLargestCluster && !s.foreground;
  const DistinctRows distinct = distinctRows(s.packed, s.dims);
  // Sizes in voxels: the peak opacity of a widget goes down with the voxels it selects.
  options.weights = distinct.multiplicity.data();
  options.rayLength = this->LastForegroundRayLength;
  // One distinct point is one cluster, the one SkipLargestCluster leaves out: the domain
  // is still a valid output, only the suggestion is empty.
  const std::size_t distinctCount = distinct.multiplicity.size();
  const bool onlyBackground = options.skipLargest && distinctCount < 2;
  const mcv::WidgetSeeding seeding = onlyBackground
    ? mcv::WidgetSeeding()
    : mcv::seedGaussianWidgets({ distinct.rows.data(), distinctCount, s.dims }, options);
  if (!seeding.ok())
  {
    vtkErrorMacro(<< seeding.error);
    return false;
  }
  if (onlyBackground)
  {
    vtkWarningMacro(<< this->SeedWidgetCount << " widgets asked for, none seeded: the sample has "
                    << "only 1 distinct reduced coordinate, the largest cluster, which "
                    << "SkipLargestCluster leaves out as the background; turn SkipLargestCluster "
                    << "off to seed a widget there.");
  }
  else if (static_cast<int>(seeding.widgets.size()) < this->SeedWidgetCount)
  {
    vtkWarningMacro(<< this->SeedWidgetCount << " widgets asked for, " << seeding.widgets.size()
                    << " seeded: the sample has only " << distinctCount << " distinct reduced coordinates.");
  }
  for (double v : mcv::flattenGaussianWidgets(seeding.widgets))
  {
    this->Internals->SeededWidgets->InsertNextValue(v);
  }
  for (std::size_t w = 0; w < seeding.widgets.size(); ++w)
  {
    this->Internals->SeededWidgetDetails->InsertNextValue(seeding.shares[w]);
    this->Internals->SeededWidgetDetails->InsertNextValue(seeding.hidden[w] ? 1.0 : 0.0);
    this->Internals->SeededWidgetDetails->InsertNextValue(seeding.meanWeights[w]);
  }
  if (!onlyBackground)
  {
    // The seeded widget of every sampled point (-1: none, e.g. the skipped background):
    // what each widget selects, for names and legends.
    vtkNew<vtkIntArray> seededWidget;
    seededWidget->SetName("SeededWidget");
    seededWidget->SetNumberOfTuples(s.m);
    for (vtkIdType i = 0; i < s.m; ++i)
    {
      seededWidget->SetValue(i, std::max(-1, seeding.labels[static_cast<std::size_t>(distinct.of[i])]));
    }
    outPD->AddArray(seededWidget);
  }
  if (widgets.widgets.empty())
  {
    shown = seeding.widgets; // nothing set yet: show the suggestion
  }
  return true;
}
