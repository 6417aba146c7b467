#include "vtkMergeChannels.h"

#include "../Common/mcvLabelTables.h"
#include "vtkFieldData.h"
#include "vtkStringArray.h"

#include "../Common/mcvFileNames.h"     // fileStem, isGenericReaderArrayName
#include "../Common/mcvInternalArrays.h" // isInternalArray

#include "vtkAbstractArray.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkFileSeriesReader.h"
#include "vtkImageData.h"
#include "vtkImageReader2.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include <cmath>
#include <set>
#include <sstream>

vtkStandardNewMacro(vtkMergeChannels);

namespace
{
struct Grid
{
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  double spacing[3] = { 1, 1, 1 };
  double origin[3] = { 0, 0, 0 };
};

Grid gridOf(vtkInformation* info)
{
  Grid g;
  info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), g.extent);
  if (info->Has(vtkDataObject::SPACING()))
  {
    info->Get(vtkDataObject::SPACING(), g.spacing);
  }
  if (info->Has(vtkDataObject::ORIGIN()))
  {
    info->Get(vtkDataObject::ORIGIN(), g.origin);
  }
  return g;
}

// Spacing and origin written by different readers may differ in the last bits.
bool close(double a, double b, double scale)
{
  return std::abs(a - b) <= 1e-6 * scale;
}

bool sameGrid(const Grid& a, const Grid& b)
{
  for (int i = 0; i < 6; ++i)
  {
    if (a.extent[i] != b.extent[i])
    {
      return false;
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    const double scale = std::abs(a.spacing[i]);
    if (!close(a.spacing[i], b.spacing[i], scale) || !close(a.origin[i], b.origin[i], scale))
    {
      return false;
    }
  }
  return true;
}

// The file an input was read from: the reader upstream of it (through filters that have
// one input), or "" when none is found. ParaView's readers of series (vtkFileSeriesReader)
// name the file of the time step read (`series` tells whether they read several, and then
// `first` is the series' first file); VTK's image readers their file.
std::string fileOf(vtkAlgorithm* algorithm, bool* series = nullptr, std::string* first = nullptr)
{
  for (int depth = 0; algorithm && depth < 64; ++depth)
  {
    if (auto* reader = vtkFileSeriesReader::SafeDownCast(algorithm))
    {
      const char* name = reader->GetCurrentFileName();
      name = name && *name ? name : reader->GetFileName(0);
      if (series)
      {
        *series = reader->GetNumberOfFileNames() > 1;
      }
      if (first)
      {
        *first = reader->GetFileName(0) ? reader->GetFileName(0) : "";
      }
      return name ? name : "";
    }
    if (auto* reader = vtkImageReader2::SafeDownCast(algorithm))
    {
      if (reader->GetFileName() && *reader->GetFileName())
      {
        return reader->GetFileName();
      }
      vtkStringArray* names = reader->GetFileNames();
      return names && names->GetNumberOfValues() > 0 ? names->GetValue(0) : std::string();
    }
    if (algorithm->GetNumberOfInputPorts() < 1 || algorithm->GetNumberOfInputConnections(0) < 1)
    {
      break;
    }
    algorithm = algorithm->GetInputAlgorithm(0, 0);
  }
  return "";
}

std::string describe(int input, vtkImageData* image, const Grid& g, const std::string& file)
{
  std::ostringstream os;
  os << "input " << input + 1 << " (" << (file.empty() ? "" : "file '" + file + "': ");
  vtkPointData* pd = image ? image->GetPointData() : nullptr;
  const int arrays = pd ? pd->GetNumberOfArrays() : 0;
  for (int a = 0; a < arrays; ++a)
  {
    const char* name = pd->GetArrayName(a);
    os << (a ? ", " : "") << "'" << (name ? name : "unnamed") << "'";
  }
  os << (arrays ? "" : "no point arrays") << "): " << g.extent[1] - g.extent[0] + 1 << " x "
     << g.extent[3] - g.extent[2] + 1 << " x " << g.extent[5] - g.extent[4] + 1
     << " voxels, spacing " << g.spacing[0] << " " << g.spacing[1] << " " << g.spacing[2]
     << ", origin " << g.origin[0] << " " << g.origin[1] << " " << g.origin[2];
  return os.str();
}
} // namespace

//------------------------------------------------------------------------------
int vtkMergeChannels::FillInputPortInformation(int port, vtkInformation* info)
{
  this->Superclass::FillInputPortInformation(port, info);
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkMergeChannels::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->GridsDiffer = false;
  this->ReportedError.clear();
  const int inputs = inputVector[0]->GetNumberOfInformationObjects();
  if (inputs > 0)
  {
    const Grid first = gridOf(inputVector[0]->GetInformationObject(0));
    for (int i = 1; i < inputs; ++i)
    {
      this->GridsDiffer =
        this->GridsDiffer || !sameGrid(first, gridOf(inputVector[0]->GetInformationObject(i)));
    }
  }
  return this->Superclass::RequestInformation(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkMergeChannels::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->GridsDiffer)
  {
    return this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);
  }
  // Each input whole, so that the error can name its arrays (asking every input for the
  // first one's extent is what gives AppendAttributes' extent error).
  for (int i = 0; i < inputVector[0]->GetNumberOfInformationObjects(); ++i)
  {
    vtkInformation* info = inputVector[0]->GetInformationObject(i);
    info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkMergeChannels::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->GridsDiffer)
  {
    if (!this->Superclass::RequestData(request, inputVector, outputVector))
    {
      return 0;
    }
    this->NameChannels(inputVector[0], vtkDataSet::GetData(outputVector, 0));
    return 1;
  }
  vtkInformation* firstInfo = inputVector[0]->GetInformationObject(0);
  const Grid first = gridOf(firstInfo);
  std::ostringstream os;
  os << "The channels are not on one grid: ";
  for (int i = 1; i < inputVector[0]->GetNumberOfInformationObjects(); ++i)
  {
    vtkInformation* info = inputVector[0]->GetInformationObject(i);
    const Grid g = gridOf(info);
    if (!sameGrid(first, g))
    {
      os << describe(i, vtkImageData::GetData(info), g, fileOf(this->GetInputAlgorithm(0, i)))
         << " differs from ";
    }
  }
  os << describe(0, vtkImageData::GetData(firstInfo), first, fileOf(this->GetInputAlgorithm(0, 0)))
     << ". Resample the channels onto one grid first (e.g. Resample To Image of each onto "
        "the first one's bounds and dimensions), then merge them.";
  if (os.str() != this->ReportedError)
  {
    this->ReportedError = os.str();
    vtkErrorMacro(<< this->ReportedError);
  }
  vtkDataObject::GetData(outputVector, 0)->Initialize();
  return 1;
}

//------------------------------------------------------------------------------
void vtkMergeChannels::NameChannels(vtkInformationVector* inputs, vtkDataSet* output)
{
  if (!output)
  {
    return;
  }
  vtkPointData* merged = output->GetPointData();
  while (merged->GetNumberOfArrays() > 0)
  {
    merged->RemoveArray(0);
  }
  std::set<std::string> used;
  for (int i = 0; i < inputs->GetNumberOfInformationObjects(); ++i)
  {
    vtkInformation* info = inputs->GetInformationObject(i);
    vtkDataSet* input = vtkDataSet::GetData(info);
    if (!input || input->GetNumberOfPoints() != output->GetNumberOfPoints())
    {
      continue;
    }
    vtkPointData* pd = input->GetPointData();
    std::string file; // looked up once, for the first generic name
    std::string stemOfFile;
    bool fileLooked = false;
    for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
    {
      vtkAbstractArray* array = pd->GetAbstractArray(a);
      const char* name = array->GetName();
      if (mcv::vtkhelpers::isInternalArray(name))
      {
        if (i == 0)
        {
          merged->AddArray(array); // ParaView's marks, once, as they are
        }
        continue;
      }
      std::string base = name && *name ? name : "channel";
      if (mcv::isGenericReaderArrayName(name))
      {
        if (!fileLooked)
        {
          // A time series keeps one name at every step: the series' ("vol" for vol_0,...).
          bool series = false;
          std::string firstFile;
          file = fileOf(this->GetInputAlgorithm(0, i), &series, &firstFile);
          file = series ? firstFile : file;
          fileLooked = true;
          stemOfFile = series ? mcv::seriesStem(file) : mcv::fileStem(file);
        }
        const std::string& stem = stemOfFile;
        base = stem.empty() ? base : stem;
      }
      std::string unique = base;
      for (int n = 2; used.count(unique); ++n)
      {
        unique = base + "_" + std::to_string(n);
      }
      used.insert(unique);
      vtkAbstractArray* copy = array->NewInstance();
      if (vtkDataArray* data = vtkDataArray::SafeDownCast(copy))
      {
        data->ShallowCopy(vtkDataArray::SafeDownCast(array));
      }
      else
      {
        copy->DeepCopy(array);
      }
      copy->SetName(unique.c_str());
      merged->AddArray(copy);
      // The channel's label table (an atlas's names), renamed with it (mcvLabelTables.h).
      if (auto* table = vtkStringArray::SafeDownCast(input->GetFieldData()->GetAbstractArray(
            mcv::vtkhelpers::labelTableName(name ? name : "").c_str())))
      {
        vtkNew<vtkStringArray> renamed;
        renamed->DeepCopy(table);
        renamed->SetName(mcv::vtkhelpers::labelTableName(unique).c_str());
        output->GetFieldData()->AddArray(renamed);
      }
      if (i == 0 && array == pd->GetScalars())
      {
        merged->SetActiveScalars(unique.c_str());
      }
      copy->Delete();
    }
  }
}
