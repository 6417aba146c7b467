#include "vtkBestViewpoint.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

// The VTK-free core (Filters/Core).
#include "BestViewpoint.h"
#include "GaussianTransferFunction.h"
#include "MemoryBudget.h"
#include "OpacityFunction.h"

// VTK arrays -> core channels, shared with the other filters of the suite.
#include "../Common/mcvChannelArrays.h"
#include "../Common/mcvCoordinateArrays.h" // float32 or float16 coordinates
#include "../Common/mcvPrintMembers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkBestViewpoint);
vtkCxxSetObjectMacro(vtkBestViewpoint, OpacityFunction, vtkPiecewiseFunction);

// The image's index frame -> world coordinates. An oriented image (direction matrix not
// identity) is computed in its index frame: its points are rotated and moved to its origin,
// its directions rotated and normalised. A plain image's grid already is in world
// coordinates.
struct vtkBestViewpoint::WorldFrame
{
  bool Oriented = false;
  double Origin[3] = { 0, 0, 0 };
  vtkNew<vtkMatrix3x3> Direction;

  mcv::Vec3 Point(const mcv::Vec3& p) const
  {
    if (!this->Oriented)
    {
      return p;
    }
    double in[3] = { p[0], p[1], p[2] }, out[3];
    this->Direction->MultiplyPoint(in, out);
    return { this->Origin[0] + out[0], this->Origin[1] + out[1], this->Origin[2] + out[2] };
  }

  void Vector(const mcv::Vec3& v, double out[3]) const
  {
    double in[3] = { v[0], v[1], v[2] };
    if (!this->Oriented)
    {
      std::copy(in, in + 3, out);
      return;
    }
    this->Direction->MultiplyPoint(in, out);
    const double n = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
    for (int a = 0; a < 3; ++a)
    {
      out[a] = n > 0 ? out[a] / n : 0.0;
    }
  }
};

namespace
{

// vtkPiecewiseFunction (data values -> opacity) as the core's piecewise-linear function.
// Nodes are used as they are when every segment is linear (midpoint 0.5, sharpness 0, the
// ParaView default); otherwise the function is sampled at 1024 points over its range.
// Without clamping, VTK gives 0 outside the range: two zero nodes just outside keep that.
mcv::OpacityFunction toCoreFunction(vtkPiecewiseFunction* pf)
{
  mcv::OpacityFunction f;
  const int size = pf->GetSize();
  if (size <= 0)
  {
    return f;
  }
  bool linear = true;
  for (int i = 0; i < size; ++i)
  {
    double node[4];
    pf->GetNodeValue(i, node);
    if (std::abs(node[2] - 0.5) > 1e-9 || node[3] != 0.0)
    {
      linear = false;
    }
  }
  double range[2];
  pf->GetRange(range);
  if (linear || size == 1 || !(range[1] > range[0]))
  {
    for (int i = 0; i < size; ++i)
    {
      double node[4];
      pf->GetNodeValue(i, node);
      f.x.push_back(node[0]);
      f.alpha.push_back(node[1]);
    }
  }
  else
  {
    const int samples = 1024;
    std::vector<double> table(samples);
    pf->GetTable(range[0], range[1], samples, table.data());
    for (int i = 0; i < samples; ++i)
    {
      f.x.push_back(range[0] + (range[1] - range[0]) * i / (samples - 1));
      f.alpha.push_back(table[i]);
    }
  }
  for (double& a : f.alpha)
  {
    a = std::isfinite(a) ? std::min(1.0, std::max(0.0, a)) : 0.0;
  }
  // Strictly ascending x (ParaView allows duplicate nodes: a step).
  for (std::size_t i = 1; i < f.x.size(); ++i)
  {
    if (!(f.x[i] > f.x[i - 1]))
    {
      f.x[i] = std::nextafter(f.x[i - 1], std::numeric_limits<double>::infinity());
    }
  }
  if (f.x.size() == 1)
  {
    // One node: ParaView draws that opacity everywhere (the node's value, clamped beyond
    // it), where the core reads a lone node as a step; a second, equal node says so.
    f.x.push_back(std::nextafter(f.x[0], std::numeric_limits<double>::infinity()));
    f.alpha.push_back(f.alpha[0]);
  }
  if (!pf->GetClamping())
  {
    const double eps = 1e-9 * std::max(1.0, std::abs(f.x.back() - f.x.front()));
    f.x.insert(f.x.begin(), f.x.front() - eps);
    f.alpha.insert(f.alpha.begin(), 0.0);
    f.x.push_back(f.x.back() + eps);
    f.alpha.push_back(0.0);
  }
  return f;
}

void addFieldVector(vtkFieldData* fd, const char* name, const double v[3])
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->InsertNextTuple(v);
  fd->AddArray(a);
}

} // namespace

//------------------------------------------------------------------------------
vtkBestViewpoint::vtkBestViewpoint()
{
  this->SetWidgetCoordinates("ReducedCoordinates");
}

//------------------------------------------------------------------------------
vtkBestViewpoint::~vtkBestViewpoint()
{
  this->SetOpacityFunction(nullptr);
  this->SetWidgetCoordinates(nullptr);
}

//------------------------------------------------------------------------------
vtkMTimeType vtkBestViewpoint::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->OpacityFunction)
  {
    t = std::max(t, this->OpacityFunction->GetMTime());
  }
  return t;
}

//------------------------------------------------------------------------------
int vtkBestViewpoint::GetSplitGhostLayers()
{
  return this->Method == HARRIS_PCA ? 1 + std::max(0, this->KernelWidth / 2) : -1;
}

//------------------------------------------------------------------------------
std::vector<vtkDataArray*> vtkBestViewpoint::GetDefaultChannels(vtkPointData* pd)
{
  if (vtkDataArray* scalars = pd->GetScalars())
  {
    return { scalars };
  }
  return this->Superclass::GetDefaultChannels(pd);
}

//------------------------------------------------------------------------------
void vtkBestViewpoint::ResetResults()
{
  for (int i = 0; i < 3; ++i)
  {
    this->BestViewDirection[i] = this->WorstViewDirection[i] = this->ViewUp[i] = 0.0;
    this->EigenvalueSpectrum[i] = this->ViewCenter[i] = this->DataCenter[i] = 0.0;
  }
  for (double& t : this->StageTimings)
  {
    t = 0.0;
  }
  std::fill(this->VisibleBounds, this->VisibleBounds + 6, 0.0);
  this->VisibleSupport->Initialize();
  this->ViewValid = 0;
  this->NumberOfPointsFound = 0;
  this->NumberOfNonFiniteVoxels = 0;
}

//------------------------------------------------------------------------------
bool vtkBestViewpoint::ComputeChannelOpacity(vtkImageData* image, const mcv::ImageGrid& grid,
  const mcv::GridPiece& block, std::vector<float>& opacity)
{
  const std::size_t count = grid.voxelCount();
  // Channels as the core sees them: contiguous (AOS) arrays of a supported type.
  mcv::vtkhelpers::ChannelArrays channelArrays;
  if (!this->SelectChannels(image, count, channelArrays))
  {
    return false;
  }
  const std::vector<mcv::ChannelView>& channels = channelArrays.views;
  const std::vector<std::string>& channelNames = channelArrays.labels;
  if (!this->AllProcessesReady())
  {
    return false;
  }

  mcv::OpacityFunction userFunction;
  if (this->OpacityFunction)
  {
    userFunction = toCoreFunction(this->OpacityFunction);
    if (userFunction.empty())
    {
      vtkWarningMacro("The opacity function has no nodes: using each channel's own range "
                      "mapped linearly to 0..1.");
    }
  }
  // Each channel's finite range (used when there is no opacity function): of the whole
  // volume, so a split run maps values like one process does.
  std::vector<double> lows(channels.size()), highs(channels.size());
  if (userFunction.empty())
  {
    for (std::size_t c = 0; c < channels.size(); ++c)
    {
      const std::pair<double, double> range = mcv::finiteRange(channels[c], count);
      lows[c] = range.first;
      highs[c] = range.second;
    }
    if (const mcv::Communicator* comm = this->GetCommunicator())
    {
      comm->min(lows);
      comm->max(highs);
    }
  }
  opacity.assign(count, 0.0f);
  std::size_t blockNonFinite = 0; // values in this process's block, ghosts included
  for (std::size_t c = 0; c < channels.size(); ++c)
  {
    mcv::OpacityFunction f = userFunction;
    if (f.empty())
    {
      const std::pair<double, double> range(lows[c], highs[c]);
      if (!(range.first <= range.second))
      {
        vtkWarningMacro("Channel " << channelNames[c]
                                   << " holds no finite value: it adds no opacity.");
        blockNonFinite += count;
        continue;
      }
      if (range.first == range.second)
      {
        vtkWarningMacro("Channel " << channelNames[c] << " is constant (" << range.first
                                   << "): it adds no opacity.");
        blockNonFinite += mcv::accumulateOpacity(channels[c], count,
          mcv::OpacityFunction{ { range.first }, { 0.0 } }, opacity.data());
        continue;
      }
      f = mcv::OpacityFunction::ramp(range.first, range.second);
    }
    blockNonFinite += mcv::accumulateOpacity(channels[c], count, f, opacity.data());
    this->UpdateProgress(0.05 * (c + 1) / channels.size());
  }
  // Counted on owned voxels (a second pass only where the block has any) and summed, so a
  // split run reports the whole volume's number.
  std::vector<double> nonFinite{ blockNonFinite > 0
      ? static_cast<double>(mcv::countNonFiniteVoxels(channels, grid, block))
      : 0.0 };
  if (const mcv::Communicator* comm = this->GetCommunicator())
  {
    comm->sum(nonFinite);
  }
  this->NumberOfNonFiniteVoxels = static_cast<vtkIdType>(nonFinite[0]);
  if (this->NumberOfNonFiniteVoxels > 0)
  {
    vtkWarningMacro(<< this->NumberOfNonFiniteVoxels
                    << " voxel(s) hold NaN/Inf in the selected channels: they were given opacity 0.");
  }
  this->WarnIfFewVisibleVoxels(grid, block, opacity, userFunction.empty(), channelNames, lows, highs);
  return true;
}

//------------------------------------------------------------------------------
// A few extreme values (one 3e38 voxel in a [0, 1] volume) stretch the default ramp so far
// that nothing else gets any opacity, and those voxels alone decide the view: say so.
void vtkBestViewpoint::WarnIfFewVisibleVoxels(const mcv::ImageGrid& grid,
  const mcv::GridPiece& block, const std::vector<float>& opacity, bool defaultRamps,
  const std::vector<std::string>& channelNames, const std::vector<double>& lows,
  const std::vector<double>& highs)
{
  const double fewVoxels = 27; // one 3x3x3 neighbourhood
  const double wholeVolume = static_cast<double>(block.wholeDims[0]) * block.wholeDims[1] *
    block.wholeDims[2];
  std::vector<double> visible{ static_cast<double>(
    mcv::countOwnedAtLeast(opacity.data(), grid, block, 0.01f)) };
  if (const mcv::Communicator* comm = this->GetCommunicator())
  {
    comm->sum(visible);
  }
  if (visible[0] == 0 || visible[0] >= fewVoxels || wholeVolume < 100 * fewVoxels)
  {
    return;
  }
  std::ostringstream os;
  os << "Only " << visible[0] << " of " << wholeVolume
     << " voxels have an opacity of 1% or more: they alone decide the view. ";
  if (defaultRamps)
  {
    os << "The opacity ramps span each channel's whole range (";
    for (std::size_t c = 0; c < channelNames.size(); ++c)
    {
      os << (c ? ", " : "") << channelNames[c] << ": " << lows[c] << " to " << highs[c];
    }
    os << "); if a few extreme values set that range, give an OpacityFunction over the "
          "values of interest (or clip the channel).";
  }
  else
  {
    os << "If that is not intended, check the OpacityFunction against the channels' values.";
  }
  vtkWarningMacro(<< os.str());
}

//------------------------------------------------------------------------------
bool vtkBestViewpoint::ComputeWidgetOpacity(vtkImageData* image, const mcv::ImageGrid& grid,
  const mcv::GridPiece& block, std::vector<float>& opacity)
{
  const std::size_t count = grid.voxelCount();
  const mcv::WidgetList widgets = this->ParseGaussianWidgets();
  if (!widgets.ok())
  {
    vtkErrorMacro(<< widgets.error);
    return false;
  }
  this->ReportWarnings(widgets.warnings);
  const char* name = this->WidgetCoordinates ? this->WidgetCoordinates : "";
  vtkDataArray* coordinates = image->GetPointData()->GetArray(name);
  if (!coordinates)
  {
    vtkErrorMacro("OpacitySource is the Gaussian widgets, but the input has no point array '"
      << name << "' with the coordinates they are placed in (run DimensionReduction first).");
    return false;
  }
  const int components = coordinates->GetNumberOfComponents();
  if ((components != 2 && components != 3) ||
    static_cast<std::size_t>(coordinates->GetNumberOfTuples()) != count)
  {
    vtkErrorMacro("The widget coordinates '" << name << "' must have 2 or 3 components and one "
      "tuple per voxel (it has " << components << " component(s), "
      << coordinates->GetNumberOfTuples() << " tuples).");
    return false;
  }
  // The core reads contiguous float32 or float16 (decoded per block); other layouts are
  // converted once.
  mcv::CoordinateView view{ nullptr, count, components };
  view.halves = mcv::vtkhelpers::halfCoordinates(coordinates);
  std::vector<float> converted;
  if (!view.halves)
  {
    view.data = mcv::vtkhelpers::coordinatesAsFloats(coordinates, converted);
  }
  if (!this->AllProcessesReady())
  {
    return false;
  }
  opacity.assign(count, 0.0f);
  const mcv::TransferFunctionRun run =
    mcv::gaussianWidgetOpacity(view, widgets.widgets, opacity.data(), this->GetRequestedDevice());
  if (!run.ok())
  {
    vtkErrorMacro(<< run.error);
    return false;
  }
  this->ReportWarnings(run.warnings);
  // Voxels whose coordinates are NaN/Inf got opacity 0 (the core's rule, as the
  // representation draws them): count them over the owned voxels of every process and say
  // so, since such holes can decide where the interest points are.
  std::vector<double> nonFinite{ 0.0 };
  if (view.halves)
  {
    // A binary16 value is NaN or Inf when its exponent bits are all set.
    std::size_t bad = 0;
    std::size_t t = 0;
    for (int k = 0; k < grid.dims[2]; ++k)
    {
      for (int j = 0; j < grid.dims[1]; ++j)
      {
        for (int i = 0; i < grid.dims[0]; ++i, ++t)
        {
          bool finite = true;
          for (int c = 0; c < components; ++c)
          {
            finite = finite && (view.halves[t * components + c] & 0x7C00u) != 0x7C00u;
          }
          bad += (!finite && block.owns(i, j, k)) ? 1 : 0;
        }
      }
    }
    nonFinite[0] = static_cast<double>(bad);
  }
  else
  {
    std::vector<mcv::ChannelView> coordinateViews;
    for (int c = 0; c < components; ++c)
    {
      coordinateViews.push_back({ view.data, mcv::ScalarType::Float32, components, c });
    }
    nonFinite[0] = static_cast<double>(mcv::countNonFiniteVoxels(coordinateViews, grid, block));
  }
  if (const mcv::Communicator* comm = this->GetCommunicator())
  {
    comm->sum(nonFinite);
  }
  this->NumberOfNonFiniteVoxels = static_cast<vtkIdType>(nonFinite[0]);
  if (this->NumberOfNonFiniteVoxels > 0)
  {
    vtkWarningMacro(<< this->NumberOfNonFiniteVoxels << " voxel(s) have NaN/Inf in the widget "
                    << "coordinates '" << name << "': they were given opacity 0.");
  }
  // The background (Foreground 0, MultichannelFeatures' mask) is transparent, as the
  // representation draws it: its coordinates are extrapolated from foreground reference
  // voxels and would otherwise take a widget's opacity and turn the volume into a box.
  vtkUnsignedCharArray* mask =
    vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetAbstractArray("Foreground"));
  if (mask && mask->GetNumberOfComponents() == 1 &&
    static_cast<std::size_t>(mask->GetNumberOfTuples()) == count)
  {
    const unsigned char* foreground = mask->GetPointer(0);
    for (std::size_t v = 0; v < count; ++v)
    {
      opacity[v] = foreground[v] ? opacity[v] : 0.0f;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkBestViewpoint::RequestMultichannelData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->ResetResults();
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!output)
  {
    vtkErrorMacro("No output polydata.");
    return 0;
  }
  mcv::ImageGrid grid;
  mcv::GridPiece block;
  vtkImageData* image = this->CheckArguments(inputVector, grid, block);
  if (!image)
  {
    return 0;
  }

  this->UpdateProgress(0.0);
  std::vector<float> opacity;
  const bool opacityOk = this->OpacitySource == OPACITY_GAUSSIAN_WIDGETS
    ? this->ComputeWidgetOpacity(image, grid, block, opacity)
    : this->ComputeChannelOpacity(image, grid, block, opacity);
  if (!opacityOk)
  {
    return 0;
  }

  WorldFrame frame;
  this->PlaceGrid(image, grid, block, frame);
  this->ComputeVisibleShape(opacity, grid, block, frame);
  mcv::BestViewpointResult result;
  if (!this->ComputeView(opacity, grid, block, frame, result))
  {
    return 0;
  }
  this->WriteOutput(outputVector, result, frame, output);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
vtkImageData* vtkBestViewpoint::CheckArguments(
  vtkInformationVector** inputVector, mcv::ImageGrid& grid, mcv::GridPiece& block)
{
  vtkImageData* image =
    this->GetInputImage(inputVector, "(resample other data to an image first).");
  if (!image)
  {
    return nullptr;
  }
  if (this->NumberOfInterestPoints <= 0)
  {
    vtkErrorMacro("NumberOfInterestPoints must be positive (got "
      << this->NumberOfInterestPoints << ").");
    return nullptr;
  }
  if (!this->GetImageBlock(image, grid, block))
  {
    return nullptr;
  }
  if (this->ReportError(mcv::checkViewpointMemory(grid.voxelCount())))
  {
    return nullptr;
  }
  return image;
}

//------------------------------------------------------------------------------
void vtkBestViewpoint::PlaceGrid(
  vtkImageData* image, mcv::ImageGrid& grid, const mcv::GridPiece& block, WorldFrame& frame)
{
  // Voxel (0,0,0) of the arrays is at extent-minimum; an oriented image (direction
  // matrix not identity) is computed in its index frame and rotated back afterwards.
  int extent[6];
  image->GetExtent(extent);
  double spacing[3];
  image->GetSpacing(spacing);
  image->GetOrigin(frame.Origin);
  // A negative spacing runs its axis backwards (VTK allows it): the same voxels as a
  // positive spacing with that axis of the direction matrix negated, which the oriented
  // path handles (the Harris response does not depend on an axis' sign).
  if (image->GetDirectionMatrix())
  {
    frame.Direction->DeepCopy(image->GetDirectionMatrix());
  }
  for (int a = 0; a < 3; ++a)
  {
    if (spacing[a] < 0)
    {
      spacing[a] = -spacing[a];
      for (int r = 0; r < 3; ++r)
      {
        frame.Direction->SetElement(r, a, -frame.Direction->GetElement(r, a));
      }
    }
  }
  frame.Oriented = !frame.Direction->IsIdentity();
  for (int a = 0; a < 3; ++a)
  {
    grid.spacing[a] = spacing[a];
    grid.origin[a] = (frame.Oriented ? 0.0 : frame.Origin[a]) + extent[2 * a] * spacing[a];
  }
  // The centre of the whole volume (a split run holds only a block of it).
  mcv::Vec3 center;
  for (int a = 0; a < 3; ++a)
  {
    const double first = grid.origin[a] - block.offset[a] * spacing[a];
    center[a] = first + 0.5 * (block.wholeDims[a] - 1) * spacing[a];
  }
  center = frame.Point(center);
  std::copy(center.begin(), center.end(), this->DataCenter);
}

namespace
{
// The directions of VisibleSupport: the six axes (their support values are the bounds)
// and 122 more spread evenly over the sphere (a Fibonacci lattice), so that the support
// points' hull is within ~1 % of the visible voxels' hull seen from any direction.
std::vector<mcv::Vec3> supportDirections()
{
  std::vector<mcv::Vec3> d{ { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
    { 0, 0, -1 } };
  const int n = 122;
  const double golden = std::acos(-1.0) * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i)
  {
    const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(1.0 - z * z);
    d.push_back({ r * std::cos(golden * i), r * std::sin(golden * i), z });
  }
  return d;
}

// The point of `points` furthest along a direction and how far (-inf: none).
struct Support
{
  double value = -HUGE_VAL;
  double point[3] = { 0, 0, 0 };
};
} // namespace

//------------------------------------------------------------------------------
void vtkBestViewpoint::ComputeVisibleShape(const std::vector<float>& opacity,
  const mcv::ImageGrid& grid, const mcv::GridPiece& block, const WorldFrame& frame)
{
  // The hull of the visible voxels is that of a few of them (their rows' ends on each
  // slice's hull), taken to world positions.
  const std::vector<std::array<int, 3>> ends =
    mcv::ownedHullCandidatesAtLeast(opacity.data(), grid, block, kVisibleOpacity);
  std::vector<mcv::Vec3> points(ends.size());
  for (std::size_t e = 0; e < ends.size(); ++e)
  {
    mcv::Vec3 p;
    for (int a = 0; a < 3; ++a)
    {
      p[a] = grid.origin[a] + ends[e][a] * grid.spacing[a];
    }
    points[e] = frame.Point(p);
  }
  const std::vector<mcv::Vec3> directions = supportDirections();
  const int count = static_cast<int>(directions.size());
  std::vector<Support> support(directions.size());
#pragma omp parallel for schedule(static)
  for (int d = 0; d < count; ++d)
  {
    Support& best = support[static_cast<std::size_t>(d)];
    for (const mcv::Vec3& p : points)
    {
      const double v = p[0] * directions[d][0] + p[1] * directions[d][1] + p[2] * directions[d][2];
      if (v > best.value)
      {
        best.value = v;
        std::copy(p.begin(), p.end(), best.point);
      }
    }
  }
  if (const mcv::Communicator* comm = this->GetCommunicator())
  {
    if (mcv::isDistributed(comm))
    {
      // every process's support, the furthest of them per direction
      const std::vector<Support> all = mcv::allGatherValues(*comm, support);
      for (std::size_t i = 0; i < all.size(); ++i)
      {
        Support& best = support[i % support.size()];
        best = all[i].value > best.value ? all[i] : best;
      }
    }
  }
  this->VisibleSupport->Initialize();
  this->VisibleSupport->SetNumberOfComponents(3);
  if (!(support[0].value > -HUGE_VAL))
  {
    // No voxel is visible: the input's bounds (its 8 corners through the frame).
    std::fill(this->VisibleBounds, this->VisibleBounds + 6, 0.0);
    for (int corner = 0; corner < 8; ++corner)
    {
      mcv::Vec3 p;
      for (int a = 0; a < 3; ++a)
      {
        const int index = (corner >> a) & 1 ? block.wholeDims[a] - 1 - block.offset[a] : -block.offset[a];
        p[a] = grid.origin[a] + index * grid.spacing[a];
      }
      p = frame.Point(p);
      for (int a = 0; a < 3; ++a)
      {
        this->VisibleBounds[2 * a] = corner ? std::min(this->VisibleBounds[2 * a], p[a]) : p[a];
        this->VisibleBounds[2 * a + 1] = corner ? std::max(this->VisibleBounds[2 * a + 1], p[a]) : p[a];
      }
    }
    return;
  }
  for (int a = 0; a < 3; ++a)
  {
    this->VisibleBounds[2 * a] = 0.0 - support[2 * a + 1].value; // along -axis (0 - : no -0)
    this->VisibleBounds[2 * a + 1] = support[2 * a].value;
  }
  for (const Support& s : support)
  {
    this->VisibleSupport->InsertNextTuple(s.point);
  }
}

//------------------------------------------------------------------------------
bool vtkBestViewpoint::ComputeView(const std::vector<float>& opacity,
  const mcv::ImageGrid& grid, const mcv::GridPiece& block, const WorldFrame& frame,
  mcv::BestViewpointResult& result)
{
  mcv::BestViewpointOptions options;
  options.method = static_cast<mcv::ViewMethod>(this->Method);
  options.harris.sigma = this->GaussianSigma;
  options.harris.kernelWidth = this->KernelWidth;
  options.harris.k = this->HarrisK;
  options.numberOfInterestPoints = this->NumberOfInterestPoints;
  options.device = this->GetRequestedDevice();
  options.entropy.samples = this->EntropySamples;
  options.entropy.imageSize = this->EntropyImageSize;
  options.communicator = this->GetCommunicator();
  options.piece = block;
  options.progress = this->ProgressCallback(0.05, 1.0);

  result = mcv::computeBestViewpoint(opacity.data(), grid, options);
  this->ReportWarnings(result.warnings);
  if (!result.ok())
  {
    vtkErrorMacro(<< result.error);
    return false;
  }
  this->SetDeviceUsed(result.deviceUsed);
  this->StageTimings[0] = result.timings.harrisMs;
  this->StageTimings[1] = result.timings.selectMs;
  this->StageTimings[2] = result.timings.pcaMs;
  this->StageTimings[3] = result.timings.totalMs;

  const mcv::ViewDirections& view = result.view;
  this->ViewValid = view.valid ? 1 : 0;
  if (view.valid)
  {
    frame.Vector(view.best, this->BestViewDirection);
    frame.Vector(view.worst, this->WorstViewDirection);
    frame.Vector(view.viewUp, this->ViewUp);
    const mcv::Vec3 center = frame.Point(view.center);
    for (int a = 0; a < 3; ++a)
    {
      this->EigenvalueSpectrum[a] = view.eigenvalues[a];
      this->ViewCenter[a] = center[a];
    }
  }
  else if (result.warnings.empty())
  {
    // The core says why there is no view among its warnings (reported above); a second,
    // vaguer line would only repeat it.
    vtkWarningMacro(<< (view.message.empty() ? std::string("no view direction could be found")
                                             : view.message));
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkBestViewpoint::WriteOutput(vtkInformationVector* outputVector,
  const mcv::BestViewpointResult& result, const WorldFrame& frame, vtkPolyData* output)
{
  // Interest points: piece 0 only.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int piece = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    : 0;
  const vtkIdType n = piece == 0 ? static_cast<vtkIdType>(result.points.size()) : 0;
  this->NumberOfPointsFound = static_cast<int>(result.points.size());

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkFloatArray> scores;
  scores->SetName("HarrisScore");
  scores->SetNumberOfTuples(n);
  vtkNew<vtkIdTypeArray> voxels;
  voxels->SetName("VoxelIndex");
  voxels->SetNumberOfTuples(n);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(n);
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(n + 1);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const mcv::Vec3 p = frame.Point(result.pointPositions[i]);
    points->SetPoint(i, p[0], p[1], p[2]);
    scores->SetValue(i, result.points.scores[i]);
    voxels->SetValue(i, static_cast<vtkIdType>(result.points.indices[i]));
    connectivity->SetValue(i, i);
    offsets->SetValue(i, i);
  }
  offsets->SetValue(n, n);
  vtkNew<vtkCellArray> vertices;
  vertices->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetVerts(vertices);
  output->GetPointData()->AddArray(scores);
  output->GetPointData()->SetActiveScalars("HarrisScore");
  output->GetPointData()->AddArray(voxels);

  // The view as field data.
  vtkFieldData* fd = output->GetFieldData();
  addFieldVector(fd, "BestViewDirection", this->BestViewDirection);
  addFieldVector(fd, "WorstViewDirection", this->WorstViewDirection);
  addFieldVector(fd, "ViewUp", this->ViewUp);
  addFieldVector(fd, "EigenvalueSpectrum", this->EigenvalueSpectrum);
  addFieldVector(fd, "ViewCenter", this->ViewCenter);
  addFieldVector(fd, "DataCenter", this->DataCenter);
  vtkNew<vtkIntArray> valid;
  valid->SetName("ViewValid");
  valid->InsertNextValue(this->ViewValid);
  fd->AddArray(valid);
  vtkNew<vtkStringArray> device;
  device->SetName("DeviceUsed");
  device->InsertNextValue(this->GetDeviceUsed());
  fd->AddArray(device);
}

//------------------------------------------------------------------------------
void vtkBestViewpoint::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  mcvPrintMembersMacro(os, indent, this->OpacityFunction, this->NumberOfInterestPoints,
    this->GaussianSigma, this->KernelWidth, this->HarrisK, this->Method, this->EntropySamples,
    this->EntropyImageSize, this->BestViewDirection, this->ViewValid);
}
