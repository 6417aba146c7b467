#include "vtkGaussianTFVolumeRepresentation.h"

#include "CoordinateTexture.h"           // mcv core (Filters/Core)
#include "ImageGrid.h"                   // mcv core: the spacing check
#include "GaussianTransferFunction.h"    // mcv core (Filters/Core)
#include "../Filters/Common/mcvCoordinateArrays.h" // float32 or float16 coordinates
#include "../Filters/Common/mcvWidgetValues.h" // the GaussianWidgets flat list
#include "mcvGaussianTFBricks.h"
#include "mcvGaussianTFShares.h"
#include "mcvGaussianTFShader.h"
#include "mcvGaussianTFTable.h"
#include "vtkGaussianTFVolumeMapper.h"

#include "vtkCompositeDataSet.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLegendBoxActor.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCoordinate.h"
#include "vtkPVRenderView.h"
#include "vtkPVSession.h"
#include "vtkProcessModule.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRenderer.h"
#include "vtkTextProperty.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLShaderProperty.h"
#include "vtkPVLODVolume.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkScalarsToColors.h"
#include "vtkShader.h"
#include "vtkSmartPointer.h"
#include "vtkSmartVolumeMapper.h"
#include "vtkTimeStamp.h"
#include "vtkTimerLog.h"
#include "vtkUniforms.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedShortArray.h"
#include "vtkVolumeMapper.h"
#include "vtkVolumeProperty.h"
#include "vtkWeakPointer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
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
void anchorRanges(vtkDataArray* array, double top)
{
  const double range[2] = { 0.0, top };
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

// "" when every piece has a positive spacing; else what is wrong. VTK's ray caster draws
// nothing for a zero or negative spacing (ParaView's Volume representation neither): an
// error says so instead of a blank picture.
std::string spacingError(const std::vector<vtkImageData*>& pieces)
{
  for (vtkImageData* piece : pieces)
  {
    mcv::ImageGrid grid;
    piece->GetSpacing(grid.spacing.data());
    const std::string problem = grid.spacingProblem();
    if (!problem.empty())
    {
      const bool negative = grid.spacing[0] < 0 || grid.spacing[1] < 0 || grid.spacing[2] < 0;
      return "Nothing is drawn: " + problem +
        (negative ? "; VTK's ray caster draws nothing for a negative spacing, Resample To Image "
                    "gives the same volume a positive one."
                  : ".");
    }
  }
  return std::string();
}

bool isOwnArray(const char* name)
{
  const std::string n = name ? name : "";
  return n == vtkGaussianTFVolumeRepresentation::GetRGBAArrayName() ||
    n == vtkGaussianTFVolumeRepresentation::GetTextureArrayName();
}

std::string pointArrayNames(vtkPointData* pd)
{
  std::string names;
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    const char* name = pd->GetArrayName(i);
    if (name && !isOwnArray(name))
    {
      names += (names.empty() ? "" : ", ") + std::string(name);
    }
  }
  return names.empty() ? "none" : names;
}

// The coordinate array of a piece, or an error message saying what is wrong with it.
vtkDataArray* coordinatesOf(vtkImageData* piece, const std::string& name, std::string& error)
{
  vtkPointData* pd = piece->GetPointData();
  vtkDataArray* coords = pd->GetArray(name.c_str());
  std::ostringstream msg;
  if (!coords)
  {
    msg << "The coordinate array '" << name
        << "' is not a numeric point array of the input (point arrays: " << pointArrayNames(pd)
        << "). Select the reduced coordinates, e.g. ReducedCoordinates of DimensionReduction.";
  }
  else if (coords->GetNumberOfComponents() != 2 && coords->GetNumberOfComponents() != 3)
  {
    msg << "The coordinate array '" << name << "' has " << coords->GetNumberOfComponents()
        << " component(s); the Gaussian widgets need 2D or 3D coordinates (2 or 3 "
           "components).";
  }
  else if (coords->GetNumberOfTuples() != piece->GetNumberOfPoints())
  {
    msg << "The coordinate array '" << name << "' has " << coords->GetNumberOfTuples()
        << " tuples for " << piece->GetNumberOfPoints() << " points.";
  }
  error = msg.str();
  return error.empty() ? coords : nullptr;
}

// The mask array of a piece when it is usable (one component, one value per point).
vtkDataArray* maskOf(vtkImageData* piece, const std::string& name)
{
  vtkDataArray* mask = name.empty() ? nullptr : piece->GetPointData()->GetArray(name.c_str());
  if (mask && mask->GetNumberOfComponents() == 1 &&
    mask->GetNumberOfTuples() == piece->GetNumberOfPoints())
  {
    return mask;
  }
  return nullptr;
}

// Float32 values of `array` (no copy when it already is float32; not for float16, which
// the core decodes a chunk at a time: mcv::vtkhelpers::halfCoordinates).
const float* asFloats(vtkDataArray* array, std::vector<float>& storage)
{
  return mcv::vtkhelpers::coordinatesAsFloats(array, storage);
}

// One byte per voxel, 0 where `mask` is 0 (no copy for a uint8 mask); nullptr: no mask.
const std::uint8_t* asBytes(vtkDataArray* mask, std::vector<std::uint8_t>& storage)
{
  if (!mask)
  {
    return nullptr;
  }
  if (auto bytes = vtkUnsignedCharArray::FastDownCast(mask))
  {
    return bytes->GetPointer(0);
  }
  const vtkIdType n = mask->GetNumberOfTuples();
  storage.resize(static_cast<size_t>(n));
  for (vtkIdType t = 0; t < n; ++t)
  {
    storage[t] = mask->GetComponent(t, 0) != 0 ? 1 : 0;
  }
  return storage.data();
}

// The arrays one classification was made from: a new piece, a modified coordinate or mask
// array, or other array names make it stale.
struct InputStamp
{
  std::vector<vtkWeakPointer<vtkImageData>> Pieces;
  std::vector<vtkWeakPointer<vtkDataArray>> Arrays; // coordinates, mask, per piece
  std::vector<vtkMTimeType> MTimes;
  std::string Names;

  static std::vector<vtkDataArray*> arraysOf(const std::vector<vtkImageData*>& pieces,
    const std::string& coordinates, const std::string& mask)
  {
    std::vector<vtkDataArray*> arrays;
    for (vtkImageData* piece : pieces)
    {
      arrays.push_back(piece->GetPointData()->GetArray(coordinates.c_str()));
      arrays.push_back(maskOf(piece, mask));
    }
    return arrays;
  }

  bool Changed(const std::vector<vtkImageData*>& pieces, const std::string& coordinates,
    const std::string& mask) const
  {
    const std::vector<vtkDataArray*> arrays = arraysOf(pieces, coordinates, mask);
    if (pieces.size() != this->Pieces.size() || coordinates + '\n' + mask != this->Names)
    {
      return true;
    }
    for (size_t i = 0; i < pieces.size(); ++i)
    {
      if (pieces[i] != this->Pieces[i])
      {
        return true;
      }
    }
    for (size_t i = 0; i < arrays.size(); ++i)
    {
      if (arrays[i] != this->Arrays[i] || (arrays[i] && arrays[i]->GetMTime() != this->MTimes[i]))
      {
        return true;
      }
    }
    return false;
  }

  void Record(const std::vector<vtkImageData*>& pieces, const std::string& coordinates,
    const std::string& mask)
  {
    const std::vector<vtkDataArray*> arrays = arraysOf(pieces, coordinates, mask);
    this->Pieces.assign(pieces.begin(), pieces.end());
    this->Arrays.assign(arrays.begin(), arrays.end());
    this->MTimes.clear();
    for (vtkDataArray* a : arrays)
    {
      this->MTimes.push_back(a ? a->GetMTime() : 0);
    }
    this->Names = coordinates + '\n' + mask;
  }
};
} // namespace

struct vtkGaussianTFVolumeRepresentation::vtkInternals
{
  mcv::vtkhelpers::WidgetValues WidgetValues; // flat, 8 per widget
  std::string CoordinateArray = "ReducedCoordinates";
  std::string MaskArray = "Foreground";
  vtkTimeStamp SettingsTime; // widgets, arrays, device or classification changed
  vtkTimeStamp ComputeTime;  // last (attempted) classification update

  InputStamp RGBAInputs;    // what the RGBA arrays were computed from
  InputStamp TextureInputs; // what the coordinate textures were built from
  mcv::CoordinateRange TextureRange;
  int TextureComponents = 3;
  mcv::bricks::BrickBounds Bricks; // of the one piece's texture; empty: no table
  bool UseBricks = false;          // the shader reads the widget table
  bool UseTable = false;           // the shader reads the baked table
  std::string EvaluationUsed;      // per sample: the table's size, or why every widget

  bool Valid = false;
  std::string DeviceUsed;
  std::vector<std::string> LastRunWarnings; // reported once, not per computation
  std::vector<float> Converted;             // non-float32 coordinates as float32
  std::vector<std::uint8_t> ConvertedMask;  // a non-uint8 mask as bytes

  // Byte alpha -> opacity: the identity (two points, so that the ray caster's opacity table
  // stays small over the 16-bit range of the per-sample texture). VTK's ray caster corrects
  // the opacity of dependent (RGBA) components for the sample distance s with the unit
  // distance u of the last component, 1 - (1 - alpha)^(s/u), but ParaView sets only the
  // first one's: UpdateMapperParameters copies it there, so per voxel and per sample both
  // accumulate opacity alpha over a length u, at any spacing (a ramp carrying 1/u itself
  // rounded every opacity of the float table to 0 at u ~ 1e9).
  vtkNew<vtkPiecewiseFunction> AlphaRamp;
  vtkNew<vtkOpenGLShaderProperty> ShaderProperty; // per-sample replacements and uniforms
  std::string ShaderKey;                          // blend mode and jitter of the replacements
  std::vector<std::string> Names;   // GaussianWidgetNames
  std::vector<double> Shares;       // each widget's share of the drawn voxels
  mcv::gaussiantf::ShareCounts LocalCounts; // their counts on this process's voxels
  InputStamp ShareInputs;           // what the shares were counted on
  vtkTimeStamp ShareTime;           // when they were
  std::string LegendKey;            // what the legend shows now
  std::string LegendText;           // its rows, one per line
  vtkNew<vtkLegendBoxActor> Legend;
  vtkNew<vtkCoordinate> LegendCorner; // the view's top right corner
  vtkNew<vtkPolyData> Swatch;       // the legend's colour square
  std::vector<vtkSmartPointer<vtkPolyData>> Swatches; // one per row, in its colour
  vtkWeakPointer<vtkRenderer> LegendRenderer;
  // This process is the client of a pvserver (no data-server role): the volume is
  // classified and drawn where the data is, the legend is drawn here.
  bool ClientOfServer = false;
  bool HadWidgets = false;          // the last list checked had widgets
  bool RenderModeReported = false; // the error about a render mode without the GPU ray caster

};

vtkStandardNewMacro(vtkGaussianTFVolumeRepresentation);

//------------------------------------------------------------------------------
vtkGaussianTFVolumeRepresentation::vtkGaussianTFVolumeRepresentation()
  : Internals(new vtkInternals())
{
  // ParaView's multi-block mapper, plus passing our shader property to the rendered volume.
  this->VolumeMapper = vtkSmartPointer<vtkGaussianTFVolumeMapper>::New();
  this->Internals->AlphaRamp->AddPoint(0.0, 0.0);
  this->Internals->AlphaRamp->AddPoint(255.0, 1.0);

  // The legend: top right, white text on a dark translucent box, one square swatch per
  // widget.
  vtkNew<vtkPoints> corners;
  corners->InsertNextPoint(0, 0, 0);
  corners->InsertNextPoint(1, 0, 0);
  corners->InsertNextPoint(1, 1, 0);
  corners->InsertNextPoint(0, 1, 0);
  vtkNew<vtkCellArray> square;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  square->InsertNextCell(4, ids);
  this->Internals->Swatch->SetPoints(corners);
  this->Internals->Swatch->SetPolys(square);
  vtkLegendBoxActor* legend = this->Internals->Legend;
  // Position: pixels from the view's top right corner (its reference coordinate);
  // Position2: the box's size in pixels from Position (its own reference).
  this->Internals->LegendCorner->SetCoordinateSystemToNormalizedViewport();
  this->Internals->LegendCorner->SetValue(1.0, 1.0);
  legend->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
  legend->GetPositionCoordinate()->SetReferenceCoordinate(this->Internals->LegendCorner);
  legend->GetPosition2Coordinate()->SetCoordinateSystemToDisplay();
  legend->SetBorder(false);
  legend->SetUseBackground(true);
  legend->SetBackgroundColor(0.08, 0.08, 0.08);
  legend->SetBackgroundOpacity(0.65);
  legend->SetPadding(4);
  legend->GetEntryTextProperty()->SetColor(1, 1, 1);
  legend->GetEntryTextProperty()->SetFontFamilyToArial();
  legend->GetEntryTextProperty()->SetShadow(false);
  legend->GetEntryTextProperty()->SetBold(false);
  legend->GetEntryTextProperty()->SetItalic(false);
  legend->SetVisibility(false);
  legend->PickableOff();
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
  ++this->NumberOfDataUpdates; // classification happens at render time, on what was delivered
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
// The setters below change no pipeline state (no MarkModified): only the next render's
// classification update sees them.
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

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::ClearGaussianWidgetNames()
{
  this->Internals->Names.clear();
}

void vtkGaussianTFVolumeRepresentation::AddGaussianWidgetName(const char* name)
{
  this->Internals->Names.emplace_back(name ? name : "");
}

int vtkGaussianTFVolumeRepresentation::GetNumberOfGaussianWidgetNames()
{
  return static_cast<int>(this->Internals->Names.size());
}

const char* vtkGaussianTFVolumeRepresentation::GetGaussianWidgetName(int index)
{
  return index >= 0 && index < static_cast<int>(this->Internals->Names.size())
    ? this->Internals->Names[static_cast<size_t>(index)].c_str()
    : nullptr;
}

void vtkGaussianTFVolumeRepresentation::SetShowWidgetLegend(bool show)
{
  this->ShowWidgetLegend = show; // read at every render
  this->Internals->Legend->SetVisibility(show && !this->Internals->LegendText.empty() &&
    this->GetVisibility());
  this->Internals->LegendKey.clear();
}

const char* vtkGaussianTFVolumeRepresentation::GetWidgetLegendText()
{
  return this->Internals->LegendText.c_str();
}

void vtkGaussianTFVolumeRepresentation::SetVisibility(bool visible)
{
  this->Superclass::SetVisibility(visible);
  // A hidden volume takes its legend with it (no render-time update runs for it).
  this->Internals->Legend->SetVisibility(
    visible && this->ShowWidgetLegend && !this->Internals->LegendText.empty());
  this->Internals->LegendKey.clear();
}

int vtkGaussianTFVolumeRepresentation::GetNumberOfWidgetShares()
{
  return static_cast<int>(this->Internals->Shares.size());
}

double vtkGaussianTFVolumeRepresentation::GetWidgetShare(int index)
{
  return index >= 0 && index < static_cast<int>(this->Internals->Shares.size())
    ? this->Internals->Shares[static_cast<size_t>(index)]
    : -1.0;
}

//------------------------------------------------------------------------------
bool vtkGaussianTFVolumeRepresentation::AddToView(vtkView* view)
{
  if (auto rview = vtkPVRenderView::SafeDownCast(view))
  {
    vtkRenderer* renderer = rview->GetRenderer(vtkPVRenderView::NON_COMPOSITED_RENDERER);
    renderer->AddActor2D(this->Internals->Legend);
    this->Internals->LegendRenderer = renderer;
    // In client-server, the server renders the volume and sends its image; the client
    // draws the non-composited (annotation) renderer over it, as it does ParaView's text
    // and scalar bar annotations. The server's own legend is never seen there.
    vtkProcessModule* pm = vtkProcessModule::GetProcessModule();
    auto session = pm ? vtkPVSession::SafeDownCast(pm->GetActiveSession()) : nullptr;
    this->Internals->ClientOfServer = session &&
      session->HasProcessRole(vtkPVSession::CLIENT) &&
      !session->HasProcessRole(vtkPVSession::DATA_SERVER);
  }
  return this->Superclass::AddToView(view);
}

bool vtkGaussianTFVolumeRepresentation::RemoveFromView(vtkView* view)
{
  if (this->Internals->LegendRenderer)
  {
    this->Internals->LegendRenderer->RemoveActor2D(this->Internals->Legend);
    this->Internals->LegendRenderer = nullptr;
  }
  return this->Superclass::RemoveFromView(view);
}

//------------------------------------------------------------------------------
int vtkGaussianTFVolumeRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0;
  }
  // The legend's shares are counted where the data is, on this process's own piece (the
  // representation's input), when the view updates: every process of the session (the
  // processes of a split run, MPI pvbatch or pvserver, and a pvserver's client) updates
  // its views together, also one that holds no voxels, so the counts are summed over
  // all of them here and every process, the client that draws the legend included,
  // holds the whole volume's shares.
  // Only while the legend is shown (a property, so the same on every process): otherwise
  // no view update pays for the count and the exchange.
  if (request == vtkPVView::REQUEST_UPDATE() && this->ShowWidgetLegend)
  {
    vtkProcessModule* pm = vtkProcessModule::GetProcessModule();
    this->UpdateWidgetShares(imagePieces(this->Cache), this->WholeExtent,
      pm ? vtkPVSession::SafeDownCast(pm->GetActiveSession()) : nullptr);
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::UpdateWidgetShares(
  const std::vector<vtkImageData*>& pieces, const int whole[6], vtkPVSession* session)
{
  vtkInternals& internals = *this->Internals;
  const mcv::WidgetList widgets =
    mcv::parseGaussianWidgets(internals.WidgetValues.Data(), internals.WidgetValues.Size());
  // The same list on every process (its properties are): they all take the same branch.
  if (!widgets.ok() || widgets.widgets.empty())
  {
    internals.Shares.clear();
    return;
  }
  const size_t values = widgets.widgets.size() + 1;
  if (internals.SettingsTime > internals.ShareTime || internals.LocalCounts.Values.size() != values ||
    internals.ShareInputs.Changed(pieces, internals.CoordinateArray, internals.MaskArray))
  {
    std::vector<mcv::gaussiantf::SharePiece> counted;
    bool usable = true;
    for (vtkImageData* piece : pieces)
    {
      if (piece->GetNumberOfPoints() == 0)
      {
        continue; // an empty piece (a process without voxels) often has no arrays either
      }
      std::string error;
      vtkDataArray* coords = coordinatesOf(piece, internals.CoordinateArray, error);
      usable = usable && coords != nullptr; // the classification says what is wrong
      counted.push_back({ piece, coords, maskOf(piece, internals.MaskArray) });
    }
    internals.LocalCounts = usable ? mcv::gaussiantf::countShares(counted, whole, widgets)
                                   : mcv::gaussiantf::ShareCounts();
    // A process that cannot count says so with a negative drawn count, so that the sum
    // is unusable everywhere (the processes must still make the same collective call).
    internals.LocalCounts.Values.resize(values, 0.0);
    internals.LocalCounts.Values[0] = usable ? internals.LocalCounts.Values[0] : -1e300;
    internals.ShareInputs.Record(pieces, internals.CoordinateArray, internals.MaskArray);
    internals.ShareTime.Modified();
  }
  mcv::gaussiantf::ShareCounts total = internals.LocalCounts;
  mcv::gaussiantf::sumOverSession(session, total.Values);
  internals.Shares = mcv::gaussiantf::sharesOf(total);
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::UpdateLegend()
{
  vtkInternals& internals = *this->Internals;
  const mcv::WidgetList widgets =
    mcv::parseGaussianWidgets(internals.WidgetValues.Data(), internals.WidgetValues.Size());
  const std::vector<vtkImageData*> pieces = imagePieces(
    this->VolumeMapper->GetNumberOfInputConnections(0) > 0 ? this->VolumeMapper->GetInputDataObject(0, 0)
                                                           : nullptr);
  // One row per drawn widget: colour, name, share.
  std::vector<std::string> rows;
  std::vector<const mcv::GaussianWidget*> shown;
  std::ostringstream key;
  for (size_t w = 0; widgets.ok() && w < widgets.widgets.size(); ++w)
  {
    const mcv::GaussianWidget& widget = widgets.widgets[w];
    if (!(widget.opacity > 0))
    {
      continue; // hidden (the editor writes 0): not in the picture
    }
    std::ostringstream row;
    std::string name = w < internals.Names.size() ? internals.Names[w] : std::string();
    // One row per widget: a line break or tab in a name (a script's, a file's) is a space.
    std::replace_if(
      name.begin(), name.end(), [](char c) { return c == '\n' || c == '\r' || c == '\t'; }, ' ');
    row << (name.empty() ? "Widget " + std::to_string(w + 1) : name);
    if (w < internals.Shares.size())
    {
      const double percent = 100.0 * internals.Shares[w];
      row << "  " << std::fixed << std::setprecision(percent < 10 ? 1 : 0) << percent << "%";
    }
    rows.push_back(row.str());
    shown.push_back(&widget);
    key << rows.back() << '|' << widget.color[0] << ',' << widget.color[1] << ','
        << widget.color[2] << '\n';
  }
  // Rows of 20 pixels (text of about 14) in a view 560 pixels tall or more, smaller in a
  // smaller view down to 13 (text of about 9, still readable): a fixed size covered a
  // fifth of a 320 x 240 frame and the top of the volume that fills it.
  int* viewSize = internals.LegendRenderer ? internals.LegendRenderer->GetSize() : nullptr;
  const int viewHeight = viewSize && viewSize[1] > 0 ? viewSize[1] : 600;
  const double rowPixels = std::min(20.0, std::max(13.0, std::round(viewHeight / 28.0)));
  // At most 16 rows, and no taller than half the view: the rest is one row that counts
  // them (10 000 widgets would make a box 200 000 pixels tall that veils the whole view).
  const size_t kLegendRows = std::max<size_t>(2,
    std::min<size_t>(16, static_cast<size_t>(std::max(0.0, (viewHeight / 2 - 8) / rowPixels))));
  key << kLegendRows << '|' << rowPixels << '|';
  static const mcv::GaussianWidget moreSwatch = [] {
    mcv::GaussianWidget grey;
    grey.color[0] = grey.color[1] = grey.color[2] = 0.5;
    return grey;
  }();
  if (rows.size() > kLegendRows)
  {
    const size_t more = rows.size() - (kLegendRows - 1);
    rows.resize(kLegendRows - 1);
    shown.resize(kLegendRows - 1);
    rows.push_back("+ " + std::to_string(more) + " more widgets");
    shown.push_back(&moreSwatch);
    key << rows.back() << '\n';
  }
  // Only with the volume it explains: not for a volume drawn as nothing (an error). A
  // client whose volume stays on the server (nothing delivered here: it renders remotely)
  // classifies nothing itself, so it has no such error to go by; it shows the legend from
  // the widget list it holds (names and colours; the shares need the voxels). A client
  // rendering locally gets the volume delivered and classifies it like a built-in session.
  const bool drawnElsewhere = internals.ClientOfServer && pieces.empty();
  const bool visible = this->ShowWidgetLegend && !rows.empty() && this->GetVisibility() &&
    (internals.Valid || drawnElsewhere);
  key << visible;
  if (key.str() == internals.LegendKey)
  {
    return;
  }
  internals.LegendKey = key.str();
  internals.LegendText.clear();
  for (const std::string& row : rows)
  {
    internals.LegendText += (internals.LegendText.empty() ? "" : "\n") + row;
  }
  vtkLegendBoxActor* legend = internals.Legend;
  legend->SetVisibility(visible);
  if (rows.empty())
  {
    return;
  }
  legend->SetNumberOfEntries(static_cast<int>(rows.size()));
  size_t longest = 0;
  internals.Swatches.clear();
  for (size_t r = 0; r < rows.size(); ++r)
  {
    // The swatch carries its colour as cell scalars; the entry colour stays unset (-1),
    // so the text keeps the legend's white (an entry colour would tint the text too).
    auto swatch = vtkSmartPointer<vtkPolyData>::New();
    swatch->ShallowCopy(internals.Swatch);
    vtkNew<vtkUnsignedCharArray> colour;
    colour->SetNumberOfComponents(3);
    for (int c = 0; c < 3; ++c)
    {
      colour->InsertNextValue(static_cast<unsigned char>(
        std::lround(255.0 * std::min(1.0, std::max(0.0, shown[r]->color[c])))));
    }
    swatch->GetCellData()->SetScalars(colour);
    internals.Swatches.push_back(swatch);
    double unset[3] = { -1, -1, -1 };
    // vtkLegendBoxActor sets the text right against the swatch; a leading space is the gap.
    const std::string entry = " " + rows[r];
    legend->SetEntry(static_cast<int>(r), swatch.Get(), entry.c_str(), unset);
    longest = std::max(longest, entry.size());
  }
  // Top right, sized in pixels (the legend box scales its text to the box): rowPixels a
  // row, 0.4 of it a character plus the swatch; half a row from the view's corner.
  const double height = rowPixels * static_cast<double>(rows.size()) + 8.0;
  const double width = 2.2 * rowPixels + 0.4 * rowPixels * static_cast<double>(longest);
  const double gap = std::round(rowPixels / 2);
  legend->GetPositionCoordinate()->SetValue(-width - gap, -height - gap);
  legend->GetPosition2Coordinate()->SetValue(width, height);
}

//------------------------------------------------------------------------------
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

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::SetMaskArray(const char* name)
{
  const std::string value = name ? name : "";
  if (value != this->Internals->MaskArray)
  {
    this->Internals->MaskArray = value;
    this->Internals->SettingsTime.Modified();
  }
}

const char* vtkGaussianTFVolumeRepresentation::GetMaskArray()
{
  return this->Internals->MaskArray.c_str();
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::SetClassification(int mode)
{
  mode = mode == PER_VOXEL ? PER_VOXEL : PER_SAMPLE;
  if (mode != this->Classification)
  {
    this->Classification = mode;
    this->Internals->SettingsTime.Modified();
  }
}

void vtkGaussianTFVolumeRepresentation::SetJittering(bool jittering)
{
  this->Jittering = jittering; // read at every render
}

void vtkGaussianTFVolumeRepresentation::SetEmptySpaceSkipping(int skipping)
{
  skipping = skipping == SKIPPING_OFF || skipping == SKIPPING_ON ? skipping : SKIPPING_AUTOMATIC;
  if (skipping != this->EmptySpaceSkipping)
  {
    this->EmptySpaceSkipping = skipping;
    this->Internals->SettingsTime.Modified(); // the widget table, at the next render
  }
}

void vtkGaussianTFVolumeRepresentation::SetPerSampleEvaluation(int evaluation)
{
  evaluation = evaluation == EVALUATE_EXACT ? EVALUATE_EXACT : EVALUATE_TABLE;
  if (evaluation != this->PerSampleEvaluation)
  {
    this->PerSampleEvaluation = evaluation;
    this->Internals->SettingsTime.Modified(); // the table or the uniforms, at the next render
  }
}

const char* vtkGaussianTFVolumeRepresentation::GetEvaluationUsed()
{
  return this->Internals->EvaluationUsed.c_str();
}

void vtkGaussianTFVolumeRepresentation::SetRequestedRenderMode(int mode)
{
  if (mode != this->RequestedRenderMode)
  {
    this->RequestedRenderMode = mode;
    this->Internals->SettingsTime.Modified(); // may switch between per sample and per voxel
  }
  this->Superclass::SetRequestedRenderMode(mode);
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
  // Only these two make sense for colours decided by the widgets.
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
bool vtkGaussianTFVolumeRepresentation::GPURayCasterRequested()
{
  // Both classifications need VTK's GPU ray caster: the shader replacements exist there
  // only, and ParaView's CPU ray caster ("Ray Cast Only") takes no multi-component data,
  // so it would draw nothing per voxel either (seen with ParaView 5.11: "Data array
  // GaussianTF_RGBA is not supported by FixedPointVolumeRCMapper").
  const bool gpu = this->RequestedRenderMode == vtkSmartVolumeMapper::DefaultRenderMode ||
    this->RequestedRenderMode == vtkSmartVolumeMapper::GPURenderMode;
  if (!gpu && !this->Internals->RenderModeReported)
  {
    vtkErrorMacro(<< "The Gaussian TF Volume is drawn by the GPU ray caster only: set Volume "
                     "Rendering Mode to 'Smart' or 'GPU Based' (nothing is drawn with '"
                  << (this->RequestedRenderMode == vtkSmartVolumeMapper::RayCastRenderMode
                         ? "Ray Cast Only"
                         : "OSPRay Based")
                  << "').");
  }
  this->Internals->RenderModeReported = !gpu;
  return gpu;
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::ReportWidgetWarnings(const mcv::WidgetList& widgets)
{
  // A representation just chosen has no widgets yet: the expected first state, not worth
  // a warning (it would open the GUI's Output Messages window). Emptying a list that had
  // widgets is still said.
  const bool firstEmpty = widgets.widgets.empty() && !this->Internals->HadWidgets;
  this->Internals->HadWidgets = !widgets.widgets.empty();
  if (firstEmpty)
  {
    return;
  }
  for (const std::string& warning : widgets.warnings)
  {
    vtkWarningMacro(<< warning);
  }
}

//------------------------------------------------------------------------------
bool vtkGaussianTFVolumeRepresentation::UpdateRGBA()
{
  vtkInternals& internals = *this->Internals;
  const std::vector<vtkImageData*> pieces = imagePieces(
    this->VolumeMapper->GetNumberOfInputConnections(0) > 0 ? this->VolumeMapper->GetInputDataObject(0, 0)
                                                           : nullptr);
  const bool settingsChanged = internals.SettingsTime > internals.ComputeTime;
  if (!settingsChanged &&
    !internals.RGBAInputs.Changed(pieces, internals.CoordinateArray, internals.MaskArray))
  {
    return internals.Valid;
  }
  internals.ComputeTime.Modified();
  internals.EvaluationUsed.clear(); // per sample only
  internals.RGBAInputs.Record(pieces, internals.CoordinateArray, internals.MaskArray);
  internals.Valid = false;
  if (pieces.empty())
  {
    return false; // nothing delivered here (a rank without data): nothing to draw
  }
  const std::string badSpacing = spacingError(pieces);
  if (!badSpacing.empty())
  {
    vtkErrorMacro(<< badSpacing);
    return false;
  }

  const mcv::WidgetList widgets =
    mcv::parseGaussianWidgets(internals.WidgetValues.Data(), internals.WidgetValues.Size());
  if (!widgets.ok())
  {
    vtkErrorMacro(<< widgets.error << " Nothing is drawn until the list is fixed.");
    return false;
  }
  if (settingsChanged)
  {
    this->ReportWidgetWarnings(widgets);
  }

  std::vector<std::string> runWarnings;
  for (vtkImageData* piece : pieces)
  {
    std::string error;
    vtkDataArray* coords = coordinatesOf(piece, internals.CoordinateArray, error);
    if (!coords)
    {
      vtkErrorMacro(<< error);
      return false;
    }
    const vtkIdType n = piece->GetNumberOfPoints();
    mcv::CoordinateView view;
    view.count = static_cast<size_t>(n);
    view.components = coords->GetNumberOfComponents();
    // The array's modification time tags its values: the GPU path keeps the coordinates
    // on the device across widget edits and uploads them again only when it changes.
    view.version = static_cast<std::uint64_t>(coords->GetMTime());
    view.halves = mcv::vtkhelpers::halfCoordinates(coords);
    view.data = view.halves ? nullptr : asFloats(coords, internals.Converted);

    vtkPointData* pd = piece->GetPointData();
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
      return false;
    }
    if (const std::uint8_t* mask =
          asBytes(maskOf(piece, internals.MaskArray), internals.ConvertedMask))
    {
      unsigned char* out = rgba->GetPointer(0);
      for (vtkIdType t = 0; t < n; ++t)
      {
        if (!mask[t])
        {
          std::fill(out + 4 * t, out + 4 * t + 4, 0); // background: transparent black
        }
      }
    }
    runWarnings.insert(runWarnings.end(), run.warnings.begin(), run.warnings.end());
    internals.DeviceUsed = mcv::deviceName(run.deviceUsed);
    if (this->Device == vtkMultichannelAlgorithm::DEVICE_AUTO && run.deviceUsed == mcv::Device::CPU)
    {
      vtkMultichannelAlgorithm::NoteAutoDeviceOnCPU();
    }
    rgba->Modified();            // new texture upload; also drops the cached ranges...
    anchorRanges(rgba, 255.0);   // ...which are set again to [0, 255] per component
  }
  if (runWarnings != internals.LastRunWarnings)
  {
    for (const std::string& warning : runWarnings)
    {
      vtkWarningMacro(<< warning);
    }
    internals.LastRunWarnings = runWarnings;
  }
  internals.Valid = true;
  ++this->NumberOfComputations;
  return true;
}

//------------------------------------------------------------------------------
bool vtkGaussianTFVolumeRepresentation::UpdatePerSample()
{
  vtkInternals& internals = *this->Internals;
  const std::vector<vtkImageData*> pieces = imagePieces(
    this->VolumeMapper->GetNumberOfInputConnections(0) > 0 ? this->VolumeMapper->GetInputDataObject(0, 0)
                                                           : nullptr);
  const bool dataChanged =
    internals.TextureInputs.Changed(pieces, internals.CoordinateArray, internals.MaskArray);
  const bool settingsChanged = internals.SettingsTime > internals.ComputeTime;
  if (!dataChanged && !settingsChanged)
  {
    return internals.Valid;
  }
  internals.ComputeTime.Modified();
  internals.Valid = false;
  const std::string badSpacing = spacingError(pieces);
  if (pieces.empty() || !badSpacing.empty())
  {
    if (!badSpacing.empty())
    {
      vtkErrorMacro(<< badSpacing);
    }
    internals.TextureInputs.Record(pieces, internals.CoordinateArray, internals.MaskArray);
    return false;
  }

  // The coordinate textures: once per data change, one range for all pieces of this rank
  // (the widgets are uniforms of the one volume prop).
  if (dataChanged)
  {
    std::vector<vtkDataArray*> coords;
    for (vtkImageData* piece : pieces)
    {
      std::string error;
      coords.push_back(coordinatesOf(piece, internals.CoordinateArray, error));
      if (!coords.back())
      {
        vtkErrorMacro(<< error);
        return false;
      }
    }
    internals.TextureComponents = coords[0]->GetNumberOfComponents();
    internals.TextureRange = mcv::CoordinateRange();
    internals.Bricks = mcv::bricks::BrickBounds();
    for (size_t p = 0; p < pieces.size(); ++p)
    {
      const std::uint8_t* mask = asBytes(maskOf(pieces[p], internals.MaskArray), internals.ConvertedMask);
      if (const std::uint16_t* halves = mcv::vtkhelpers::halfCoordinates(coords[p]))
      {
        internals.TextureRange.AddHalf(halves, coords[p]->GetNumberOfTuples(), coords[p]->GetNumberOfComponents(), mask);
        continue;
      }
      const float* x = asFloats(coords[p], internals.Converted);
      internals.TextureRange.Add(x, coords[p]->GetNumberOfTuples(), coords[p]->GetNumberOfComponents(), mask);
    }
    for (size_t p = 0; p < pieces.size(); ++p)
    {
      const vtkIdType n = pieces[p]->GetNumberOfPoints();
      vtkNew<vtkUnsignedShortArray> texels;
      texels->SetName(GetTextureArrayName());
      texels->SetNumberOfComponents(4);
      texels->SetNumberOfTuples(n);
      const std::uint8_t* mask = asBytes(maskOf(pieces[p], internals.MaskArray), internals.ConvertedMask);
      if (const std::uint16_t* halves = mcv::vtkhelpers::halfCoordinates(coords[p]))
      {
        mcv::quantizeHalfCoordinates(halves, static_cast<size_t>(n), coords[p]->GetNumberOfComponents(), mask,
          internals.TextureRange, texels->GetPointer(0));
      }
      else
      {
        mcv::quantizeCoordinates(asFloats(coords[p], internals.Converted), static_cast<size_t>(n),
          coords[p]->GetNumberOfComponents(), mask, internals.TextureRange, texels->GetPointer(0));
      }
      anchorRanges(texels, 65535.0); // the texture's range: no pass to find it
      pieces[p]->GetPointData()->AddArray(texels);
      if (pieces.size() == 1)
      {
        int dims[3];
        pieces[p]->GetDimensions(dims);
        internals.Bricks = mcv::bricks::computeBrickBounds(texels->GetPointer(0), dims);
      }
    }
    internals.Converted = std::vector<float>();
    internals.ConvertedMask = std::vector<std::uint8_t>();
    internals.TextureInputs.Record(pieces, internals.CoordinateArray, internals.MaskArray);
    ++this->NumberOfTextureBuilds;
  }

  // The widgets: uniforms only.
  const mcv::WidgetList widgets =
    mcv::parseGaussianWidgets(internals.WidgetValues.Data(), internals.WidgetValues.Size());
  if (!widgets.ok())
  {
    vtkErrorMacro(<< widgets.error << " Nothing is drawn until the list is fixed.");
    return false;
  }
  std::string error;
  std::vector<std::string> warnings;
  const std::vector<mcv::detail::PackedGaussianWidget> packed =
    mcv::detail::packGaussianWidgets(widgets.widgets, internals.TextureComponents, error, warnings);
  if (!error.empty())
  {
    vtkErrorMacro(<< "Gaussian transfer function: " << error);
    return false;
  }
  if (static_cast<int>(packed.size()) > mcv::shader::MaximumWidgets)
  {
    vtkErrorMacro(<< packed.size() << " visible Gaussian widgets: per-sample classification "
                  << "evaluates at most " << mcv::shader::MaximumWidgets
                  << " in the shader. Remove widgets, or set Classification to 'Per voxel' "
                     "(no limit).");
    return false;
  }
  if (settingsChanged)
  {
    this->ReportWidgetWarnings(widgets);
  }
  float centreK[mcv::shader::MaximumWidgets][4] = {};
  float colourLogA[mcv::shader::MaximumWidgets][4] = {};
  for (size_t i = 0; i < packed.size(); ++i)
  {
    const mcv::detail::PackedGaussianWidget& w = packed[i];
    const float ck[4] = { w.cx, w.cy, w.cz, w.k };
    const float cl[4] = { w.r, w.g, w.b, w.logA };
    std::copy(ck, ck + 4, centreK[i]);
    std::copy(cl, cl + 4, colourLogA[i]);
  }
  const mcv::CoordinateRange& range = internals.TextureRange;
  const float minimum[3] = { float(range.min[0]), float(range.min[1]),
    internals.TextureComponents == 3 ? float(range.min[2]) : 0.f };
  const float extent[3] = { float(range.Extent(0)), float(range.Extent(1)),
    internals.TextureComponents == 3 ? float(range.Extent(2)) : 0.f };
  vtkUniforms* uniforms = internals.ShaderProperty->GetFragmentCustomUniforms();
  uniforms->SetUniformi(mcv::shader::WidgetCount, static_cast<int>(packed.size()));
  auto mapper = vtkGaussianTFVolumeMapper::SafeDownCast(this->VolumeMapper);

  // The baked table (a widget edit bakes it again: nodes x widgets in reach, not voxels),
  // or every widget at every sample: by request, or when a widget is narrower than the
  // largest table resolves.
  const mcv::tftable::TableSize size = this->PerSampleEvaluation == EVALUATE_TABLE && mapper
    ? mcv::tftable::chooseTableSize(packed, minimum, extent)
    : mcv::tftable::TableSize();
  internals.UseTable = size.Valid();
  if (internals.UseTable)
  {
    const int dims[3] = { size.nodes[0], size.nodes[1], size.nodes[2] + 1 }; // + check slice
    mapper->SetTransferFunctionTable(mcv::tftable::bakeTable(packed, minimum, extent, size), dims);
    float scale[3], offset[3];
    for (int c = 0; c < 3; ++c)
    {
      scale[c] = static_cast<float>(size.nodes[c] - 1) / static_cast<float>(dims[c]);
      offset[c] = 0.5f / static_cast<float>(dims[c]);
    }
    uniforms->SetUniform3f(mcv::shader::TableScale, scale);
    uniforms->SetUniform3f(mcv::shader::TableOffset, offset);
    for (const char* name : { mcv::shader::WidgetCentreK, mcv::shader::WidgetColourLogA,
           mcv::shader::CoordinateMin, mcv::shader::CoordinateExtent })
    {
      uniforms->RemoveUniform(name); // not in the table's shader
    }
    std::ostringstream used;
    used << "table " << size.nodes[0] << "x" << size.nodes[1] << "x" << size.nodes[2];
    internals.EvaluationUsed = used.str();
  }
  else
  {
    if (mapper)
    {
      mapper->SetTransferFunctionTable(std::vector<std::uint16_t>(), size.nodes);
    }
    uniforms->RemoveUniform(mcv::shader::TableScale);
    uniforms->RemoveUniform(mcv::shader::TableOffset);
    uniforms->SetUniform4fv(mcv::shader::WidgetCentreK, mcv::shader::MaximumWidgets, centreK);
    uniforms->SetUniform4fv(mcv::shader::WidgetColourLogA, mcv::shader::MaximumWidgets, colourLogA);
    uniforms->SetUniform3f(mcv::shader::CoordinateMin, minimum);
    uniforms->SetUniform3f(mcv::shader::CoordinateExtent, extent);
    internals.EvaluationUsed =
      this->PerSampleEvaluation == EVALUATE_TABLE ? "exact: " + size.reason : "exact";
  }

  // The widget table: which widgets reach each brick (a widget edit rebuilds it: a pass
  // over the bricks, not the voxels).
  // Automatic: only with the exact evaluation (the baked table costs one fetch whatever
  // the widgets), and only where the lists leave enough out (SKIPPING_AUTOMATIC).
  const bool tryBricks = mapper && internals.Bricks.Count() > 0 &&
    (this->EmptySpaceSkipping == SKIPPING_ON ||
      (this->EmptySpaceSkipping == SKIPPING_AUTOMATIC && !internals.UseTable && !packed.empty()));
  internals.UseBricks = false;
  this->NumberOfBricks = this->NumberOfEmptyBricks = 0;
  this->MeanWidgetsPerBrick = 0;
  std::vector<float> widgetTable;
  int height = 0;
  if (tryBricks)
  {
    long long listed = 0;
    widgetTable = mcv::bricks::buildWidgetTable(
      internals.Bricks, packed, minimum, extent, height, this->NumberOfEmptyBricks, listed);
    this->NumberOfBricks = internals.Bricks.Count();
    const int reached = this->NumberOfBricks - this->NumberOfEmptyBricks;
    this->MeanWidgetsPerBrick = reached > 0 ? double(listed) / reached : 0.0;
    internals.UseBricks = this->EmptySpaceSkipping == SKIPPING_ON ||
      this->MeanWidgetsPerBrick <= AutomaticSkippingShare * static_cast<double>(packed.size());
  }
  this->SkippingUsed = internals.UseBricks;
  if (internals.UseBricks)
  {
    mapper->SetWidgetTable(widgetTable, height);
    const float volume[3] = { float(internals.Bricks.volume[0]), float(internals.Bricks.volume[1]),
      float(internals.Bricks.volume[2]) };
    const float grid[3] = { float(internals.Bricks.grid[0]), float(internals.Bricks.grid[1]),
      float(internals.Bricks.grid[2]) };
    uniforms->SetUniform3f(mcv::shader::VolumeSize, volume);
    uniforms->SetUniform3f(mcv::shader::BrickGrid, grid);
  }
  else
  {
    if (mapper)
    {
      mapper->SetWidgetTable(std::vector<float>(), 0);
    }
    uniforms->RemoveUniform(mcv::shader::VolumeSize);
    uniforms->RemoveUniform(mcv::shader::BrickGrid);
  }
  internals.DeviceUsed = "OpenGL";
  internals.Valid = true;
  ++this->NumberOfComputations;
  return true;
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::UpdateMapperParameters()
{
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  const int updatesBefore = this->NumberOfComputations + this->NumberOfTextureBuilds;
  vtkInternals& internals = *this->Internals;
  auto mapper = vtkGaussianTFVolumeMapper::SafeDownCast(this->VolumeMapper);
  const bool gpuRayCaster = this->GPURayCasterRequested();
  const bool perSample = gpuRayCaster && this->Classification == PER_SAMPLE;
  // The widgets' opacity is accumulated over the volume's Scalar Opacity Unit Distance
  // (ParaView's default: the cell diagonal, so 10 nm voxels in metres look like 1 mm ones).
  const double opacityUnit = this->Property->GetScalarOpacityUnitDistance();
  const double unitDistance = opacityUnit > 0 && std::isfinite(opacityUnit) ? opacityUnit : 1.0;
  for (int c = 1; c < 4; ++c) // per voxel: VTK reads the last component's (see AlphaRamp)
  {
    this->Property->SetScalarOpacityUnitDistance(c, unitDistance);
  }
  const bool mip = this->GaussianBlendMode == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND;
  if (perSample)
  {
    this->UpdatePerSample();
    internals.ShaderProperty->GetFragmentCustomUniforms()->SetUniformf(
      mcv::shader::UnitDistance, static_cast<float>(unitDistance));
    const bool bricks = internals.UseBricks;
    const bool table = internals.UseTable;
    const std::string key = std::string(mip ? "mip" : "composite") + (this->Jittering ? "+jitter" : "") +
      (bricks ? "+bricks" : "") + (table ? "+table" : "");
    if (key != internals.ShaderKey)
    {
      vtkOpenGLShaderProperty* sp = internals.ShaderProperty;
      sp->ClearAllFragmentShaderReplacements();
      sp->AddFragmentShaderReplacement("//VTK::Shading::Dec", true,
        "//VTK::Shading::Dec\n" + mcv::shader::ClassifyDeclaration(bricks, table), false);
      sp->AddFragmentShaderReplacement("//VTK::Shading::Init", true,
        mcv::shader::RayStart(this->Jittering, bricks, table), false);
      sp->AddFragmentShaderReplacement(
        "//VTK::Shading::Impl", true, mcv::shader::SampleAndBlend(mip, bricks), false);
      internals.ShaderKey = key;
    }
    this->VolumeMapper->SelectScalarArray(GetTextureArrayName());
    // The shader blends (composite or maximum); VTK's composite set-up is the neutral one.
    this->VolumeMapper->SetBlendMode(vtkVolumeMapper::COMPOSITE_BLEND);
  }
  else
  {
    this->UpdateRGBA();
    this->VolumeMapper->SelectScalarArray(GetRGBAArrayName());
    this->VolumeMapper->SetBlendMode(this->GaussianBlendMode);
  }
  if (mapper)
  {
    mapper->SetRenderShaderProperty(perSample ? internals.ShaderProperty.Get() : nullptr);
  }
  this->VolumeMapper->SetScalarMode(VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  this->Actor->SetMapper(this->VolumeMapper);
  // Bad input: draw nothing rather than stale or garbage colours.
  internals.Valid = internals.Valid && gpuRayCaster;
  this->Actor->SetVisibility(internals.Valid);

  if (this->VolumeMapper->GetCropping())
  {
    double planes[6];
    for (int i = 0; i < 6; i++)
    {
      planes[i] = this->CroppingOrigin[i / 2] + this->DataBounds[i] * this->CroppingScale[i / 2];
    }
    this->VolumeMapper->SetCroppingRegionPlanes(planes);
  }

  // Four dependent components (RGBA, or the coordinate texture whose classification the
  // shader replaces); A through the identity ramp. Set on every render because the shared
  // volume properties (MapScalars, ScalarOpacityFunction...) would otherwise switch it back.
  this->Property->SetIndependentComponents(false);
  this->Property->SetTransferFunctionMode(vtkVolumeProperty::TF_1D);
  this->Property->SetScalarOpacity(internals.AlphaRamp);
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
  timer->StopTimer();
  this->UpdateLegend(); // after the timer: the classification's cost is measured alone
  if (this->NumberOfComputations + this->NumberOfTextureBuilds != updatesBefore)
  {
    // Only a preparation that did work: a render calls this more than once.
    this->LastPreparationSeconds = timer->GetElapsedTime();
  }
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Classification: " << (this->Classification == PER_SAMPLE ? "per sample" : "per voxel") << "\n";
  os << indent << "Jittering: " << this->Jittering << "\n";
  os << indent << "EmptySpaceSkipping: " << this->EmptySpaceSkipping << "\n";
  os << indent << "PerSampleEvaluation: "
     << (this->PerSampleEvaluation == EVALUATE_TABLE ? "baked table" : "exact") << "\n";
  os << indent << "CoordinateArray: " << this->Internals->CoordinateArray << "\n";
  os << indent << "MaskArray: " << this->Internals->MaskArray << "\n";
  os << indent << "GaussianWidgets: " << this->Internals->WidgetValues.Size() << " values\n";
  os << indent << "Device: " << this->Device << "\n";
  os << indent << "GaussianBlendMode: " << this->GaussianBlendMode << "\n";
  os << indent << "DeviceUsed: " << this->Internals->DeviceUsed << "\n";
  os << indent << "NumberOfComputations: " << this->NumberOfComputations << "\n";
  os << indent << "NumberOfTextureBuilds: " << this->NumberOfTextureBuilds << "\n";
}
