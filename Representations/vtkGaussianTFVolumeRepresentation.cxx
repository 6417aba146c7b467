#include "vtkGaussianTFVolumeRepresentation.h"

#include "GaussianTransferFunction.h" // mcv core (Filters/Core)
#include "../Filters/Common/mcvWidgetValues.h" // the GaussianWidgets flat list

#include "vtkCompositeDataSet.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiBlockVolumeMapper.h"
#include "vtkObjectFactory.h"
#include "vtkPVLODVolume.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkScalarsToColors.h"
#include "vtkSmartPointer.h"
#include "vtkSmartVolumeMapper.h"
#include "vtkTimeStamp.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumeMapper.h"
#include "vtkVolumeProperty.h"
#include "vtkWeakPointer.h"

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace
{
// The ray caster scales every component by its own data range (vtkVolumeTexture reads
// GetFiniteRange per component) before using RGB as the colour; a red channel that peaks
// at 128 would be shown at full brightness. vtkDataArray caches the ranges in its
// information until the next Modified(): anchor them to the full byte range, so the
// texture's scale and bias are the identity on [0, 255].
void anchorByteRanges(vtkDataArray* array)
{
  const double range[2] = { 0.0, 255.0 };
  vtkInformation* info = array->GetInformation();
  const int components = array->GetNumberOfComponents();
  for (vtkInformationInformationVectorKey* key :
    { vtkAbstractArray::PER_COMPONENT(), vtkAbstractArray::PER_FINITE_COMPONENT() })
  {
    vtkNew<vtkInformationVector> perComponent;
    perComponent->SetNumberOfInformationObjects(components);
    for (int c = 0; c < components; ++c)
    {
      perComponent->GetInformationObject(c)->Set(vtkDataArray::COMPONENT_RANGE(), range, 2);
    }
    info->Set(key, perComponent);
  }
}

// The image pieces of what was delivered to this rank (an image or a partitioned set).
std::vector<vtkImageData*> imagePieces(vtkDataObject* data)
{
  if (auto image = vtkImageData::SafeDownCast(data))
  {
    return { image };
  }
  if (vtkCompositeDataSet::SafeDownCast(data))
  {
    return vtkCompositeDataSet::GetDataSets<vtkImageData>(data);
  }
  return {};
}

std::string pointArrayNames(vtkPointData* pd)
{
  std::string names;
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    const char* name = pd->GetArrayName(i);
    if (name && std::string(name) != vtkGaussianTFVolumeRepresentation::GetRGBAArrayName())
    {
      names += (names.empty() ? "" : ", ") + std::string(name);
    }
  }
  return names.empty() ? "none" : names;
}
} // namespace

struct vtkGaussianTFVolumeRepresentation::vtkInternals
{
  mcv::vtkhelpers::WidgetValues WidgetValues; // flat, 8 per widget
  std::string CoordinateArray = "ReducedCoordinates";
  vtkTimeStamp SettingsTime; // widgets, coordinate array or device changed
  vtkTimeStamp ComputeTime;  // last (attempted) computation

  // What the last computation used: a new piece or a modified coordinate array recomputes.
  std::vector<vtkWeakPointer<vtkImageData>> Pieces;
  std::vector<vtkWeakPointer<vtkDataArray>> Coordinates;
  std::vector<vtkMTimeType> CoordinatesMTime;

  bool Valid = false;
  std::string DeviceUsed;
  std::vector<std::string> LastRunWarnings; // reported once, not per computation
  std::vector<float> Converted;             // non-float32 coordinates as float32

  vtkNew<vtkPiecewiseFunction> AlphaRamp; // byte alpha -> opacity, the identity

  vtkInternals()
  {
    this->AlphaRamp->AddPoint(0.0, 0.0);
    this->AlphaRamp->AddPoint(255.0, 1.0);
  }

  bool PiecesChanged(const std::vector<vtkImageData*>& pieces, const std::string& name) const
  {
    if (pieces.size() != this->Pieces.size())
    {
      return true;
    }
    for (size_t i = 0; i < pieces.size(); ++i)
    {
      vtkDataArray* coords = pieces[i]->GetPointData()->GetArray(name.c_str());
      if (pieces[i] != this->Pieces[i] || coords != this->Coordinates[i] ||
        (coords && coords->GetMTime() != this->CoordinatesMTime[i]))
      {
        return true;
      }
    }
    return false;
  }
};

vtkStandardNewMacro(vtkGaussianTFVolumeRepresentation);

//------------------------------------------------------------------------------
vtkGaussianTFVolumeRepresentation::vtkGaussianTFVolumeRepresentation()
  : Internals(new vtkInternals())
{
}

//------------------------------------------------------------------------------
vtkGaussianTFVolumeRepresentation::~vtkGaussianTFVolumeRepresentation() = default;

//------------------------------------------------------------------------------
int vtkGaussianTFVolumeRepresentation::FillInputPortInformation(int port, vtkInformation* info)
{
  this->Superclass::FillInputPortInformation(port, info);
  // Image data only: the colours come from a per-voxel point array.
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPartitionedDataSet");
  return 1;
}

//------------------------------------------------------------------------------
int vtkGaussianTFVolumeRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  ++this->NumberOfDataUpdates; // the RGBA array is made at render time, on what was delivered
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
// The setters below change no pipeline state (no MarkModified): only the next render's
// RGBA computation sees them.
void vtkGaussianTFVolumeRepresentation::SetNumberOfGaussianWidgetValues(int count)
{
  if (this->Internals->WidgetValues.SetNumber(count))
  {
    this->Internals->SettingsTime.Modified();
  }
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::SetGaussianWidgetValue(int index, double value)
{
  if (this->Internals->WidgetValues.Set(index, value))
  {
    this->Internals->SettingsTime.Modified();
  }
}

//------------------------------------------------------------------------------
int vtkGaussianTFVolumeRepresentation::GetNumberOfGaussianWidgetValues()
{
  return this->Internals->WidgetValues.GetNumber();
}

//------------------------------------------------------------------------------
double vtkGaussianTFVolumeRepresentation::GetGaussianWidgetValue(int index)
{
  return this->Internals->WidgetValues.Get(index);
}

void vtkGaussianTFVolumeRepresentation::SetCoordinateArray(const char* name)
{
  const std::string value = name ? name : "";
  if (value != this->Internals->CoordinateArray)
  {
    this->Internals->CoordinateArray = value;
    this->Internals->SettingsTime.Modified();
  }
}

const char* vtkGaussianTFVolumeRepresentation::GetCoordinateArray()
{
  return this->Internals->CoordinateArray.c_str();
}

void vtkGaussianTFVolumeRepresentation::SetDevice(int device)
{
  device = std::max<int>(vtkMultichannelAlgorithm::DEVICE_AUTO,
    std::min<int>(device, vtkMultichannelAlgorithm::DEVICE_GPU));
  if (device != this->Device)
  {
    this->Device = device;
    this->Internals->LastRunWarnings.clear(); // a new request: say again what happened
    this->Internals->SettingsTime.Modified();
  }
}

void vtkGaussianTFVolumeRepresentation::SetGaussianBlendMode(int mode)
{
  // Only these two make sense for colours that are already decided per voxel.
  this->GaussianBlendMode = mode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND
    ? vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND
    : vtkVolumeMapper::COMPOSITE_BLEND;
}

const char* vtkGaussianTFVolumeRepresentation::GetDeviceUsed()
{
  return this->Internals->DeviceUsed.c_str();
}

int vtkGaussianTFVolumeRepresentation::GetRGBAValid()
{
  return this->Internals->Valid ? 1 : 0;
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::UpdateRGBA()
{
  vtkInternals& internals = *this->Internals;
  const std::vector<vtkImageData*> pieces =
    imagePieces(this->VolumeMapper->GetNumberOfInputConnections(0) > 0
        ? this->VolumeMapper->GetInputDataObject(0, 0)
        : nullptr);
  const bool settingsChanged = internals.SettingsTime > internals.ComputeTime;
  if (!settingsChanged && !internals.PiecesChanged(pieces, internals.CoordinateArray))
  {
    return;
  }
  internals.ComputeTime.Modified();
  internals.Valid = false;
  internals.Pieces.assign(pieces.begin(), pieces.end());
  internals.Coordinates.clear();
  internals.CoordinatesMTime.clear();
  for (vtkImageData* piece : pieces)
  {
    vtkDataArray* coords = piece->GetPointData()->GetArray(internals.CoordinateArray.c_str());
    internals.Coordinates.emplace_back(coords);
    internals.CoordinatesMTime.push_back(coords ? coords->GetMTime() : 0);
  }
  if (pieces.empty())
  {
    return; // nothing delivered here (a rank without data): nothing to draw
  }

  const mcv::WidgetList widgets = mcv::parseGaussianWidgets(
    internals.WidgetValues.Data(), internals.WidgetValues.Size());
  if (!widgets.ok())
  {
    vtkErrorMacro(<< widgets.error
                  << " Nothing is drawn until the list is fixed.");
    return;
  }
  if (settingsChanged)
  {
    for (const std::string& warning : widgets.warnings)
    {
      vtkWarningMacro(<< warning);
    }
  }

  bool ok = true;
  std::vector<std::string> runWarnings;
  for (vtkImageData* piece : pieces)
  {
    vtkPointData* pd = piece->GetPointData();
    vtkDataArray* coords = pd->GetArray(internals.CoordinateArray.c_str());
    const vtkIdType n = piece->GetNumberOfPoints();
    if (!coords)
    {
      vtkErrorMacro(<< "The coordinate array '" << internals.CoordinateArray
                    << "' is not a numeric point array of the input (point arrays: "
                    << pointArrayNames(pd)
                    << "). Select the reduced coordinates, e.g. ReducedCoordinates of "
                       "DimensionReduction.");
      ok = false;
      break;
    }
    const int components = coords->GetNumberOfComponents();
    if (components != 2 && components != 3)
    {
      vtkErrorMacro(<< "The coordinate array '" << internals.CoordinateArray << "' has "
                    << components
                    << " component(s); the Gaussian widgets need 2D or 3D coordinates "
                       "(2 or 3 components).");
      ok = false;
      break;
    }
    if (coords->GetNumberOfTuples() != n)
    {
      vtkErrorMacro(<< "The coordinate array '" << internals.CoordinateArray << "' has "
                    << coords->GetNumberOfTuples() << " tuples for " << n << " points.");
      ok = false;
      break;
    }

    mcv::CoordinateView view;
    view.count = static_cast<size_t>(n);
    view.components = components;
    // The array's modification time tags its values: the GPU path keeps the coordinates
    // on the device across widget edits and uploads them again only when it changes.
    view.version = static_cast<std::uint64_t>(coords->GetMTime());
    auto floats = vtkFloatArray::FastDownCast(coords);
    if (floats)
    {
      view.data = floats->GetPointer(0);
    }
    else
    {
      internals.Converted.resize(static_cast<size_t>(n) * components);
      for (vtkIdType t = 0; t < n; ++t)
      {
        for (int c = 0; c < components; ++c)
        {
          internals.Converted[t * components + c] =
            static_cast<float>(coords->GetComponent(t, c));
        }
      }
      view.data = internals.Converted.data();
    }

    vtkSmartPointer<vtkUnsignedCharArray> rgba =
      vtkUnsignedCharArray::SafeDownCast(pd->GetArray(GetRGBAArrayName()));
    if (!rgba || rgba->GetNumberOfComponents() != 4 || rgba->GetNumberOfTuples() != n)
    {
      rgba = vtkSmartPointer<vtkUnsignedCharArray>::New();
      rgba->SetName(GetRGBAArrayName());
      rgba->SetNumberOfComponents(4);
      rgba->SetNumberOfTuples(n);
      pd->AddArray(rgba);
    }
    const mcv::TransferFunctionRun run = mcv::applyGaussianWidgets(
      view, widgets.widgets, rgba->GetPointer(0), static_cast<mcv::Device>(this->Device));
    if (!run.ok())
    {
      vtkErrorMacro(<< "Gaussian transfer function: " << run.error);
      ok = false;
      break;
    }
    runWarnings.insert(runWarnings.end(), run.warnings.begin(), run.warnings.end());
    internals.DeviceUsed = mcv::deviceName(run.deviceUsed);
    rgba->Modified(); // new texture upload; also drops the cached ranges...
    anchorByteRanges(rgba); // ...which are set again to [0, 255] per component
  }
  if (ok && runWarnings != internals.LastRunWarnings)
  {
    for (const std::string& warning : runWarnings)
    {
      vtkWarningMacro(<< warning);
    }
    internals.LastRunWarnings = runWarnings;
  }
  internals.Valid = ok;
  ++this->NumberOfComputations;
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::UpdateMapperParameters()
{
  this->UpdateRGBA();

  this->VolumeMapper->SelectScalarArray(GetRGBAArrayName());
  this->VolumeMapper->SetScalarMode(VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  this->VolumeMapper->SetBlendMode(this->GaussianBlendMode);
  this->Actor->SetMapper(this->VolumeMapper);
  // Bad input: draw nothing rather than stale or garbage colours.
  this->Actor->SetVisibility(this->Internals->Valid);

  if (this->VolumeMapper->GetCropping())
  {
    double planes[6];
    for (int i = 0; i < 6; i++)
    {
      planes[i] = this->CroppingOrigin[i / 2] + this->DataBounds[i] * this->CroppingScale[i / 2];
    }
    this->VolumeMapper->SetCroppingRegionPlanes(planes);
  }

  // Dependent RGBA: RGB is the colour, A goes through the identity ramp. Set on every
  // render because the shared volume properties (MapScalars, ScalarOpacityFunction...)
  // would otherwise switch it back.
  this->Property->SetIndependentComponents(false);
  this->Property->SetTransferFunctionMode(vtkVolumeProperty::TF_1D);
  this->Property->SetScalarOpacity(this->Internals->AlphaRamp);
  if (auto mbMapper = vtkMultiBlockVolumeMapper::SafeDownCast(this->VolumeMapper))
  {
    mbMapper->SetVectorMode(vtkScalarsToColors::COMPONENT);
    mbMapper->SetVectorComponent(0);
  }
  else if (auto smartMapper = vtkSmartVolumeMapper::SafeDownCast(this->VolumeMapper))
  {
    smartMapper->SetVectorMode(vtkScalarsToColors::COMPONENT);
    smartMapper->SetVectorComponent(0);
  }
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CoordinateArray: " << this->Internals->CoordinateArray << "\n";
  os << indent << "GaussianWidgets: " << this->Internals->WidgetValues.Size() << " values\n";
  os << indent << "Device: " << this->Device << "\n";
  os << indent << "GaussianBlendMode: " << this->GaussianBlendMode << "\n";
  os << indent << "DeviceUsed: " << this->Internals->DeviceUsed << "\n";
  os << indent << "NumberOfComputations: " << this->NumberOfComputations << "\n";
}
