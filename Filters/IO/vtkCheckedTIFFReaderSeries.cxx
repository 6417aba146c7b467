// vtkCheckedTIFFReader: a list of volume files read as a time series, one file per step
// (microscopes and tifffile write a time-lapse as one OME-TIFF or hyperstack per time
// point). Each file is read by a vtkCheckedTIFFReader of its own, with every check of a
// single file; the series adds that every file holds one frame of the first file's grid
// and channels.
#include "vtkCheckedTIFFReader.h"

#include "CheckedReading.h"
#include "OMETiffMetadata.h"
#include "TiffDirectories.h"
#include "TiffPlaneMap.h"

#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace
{
// The grid a step's information announces: "181 x 217 x 181 voxels, spacing 1 1 1, origin 0
// 0 0" (whole extent, spacing, origin).
std::string gridOf(vtkInformation* info)
{
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  double spacing[3] = { 1, 1, 1 };
  double origin[3] = { 0, 0, 0 };
  info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  if (info->Has(vtkDataObject::SPACING()))
  {
    info->Get(vtkDataObject::SPACING(), spacing);
  }
  if (info->Has(vtkDataObject::ORIGIN()))
  {
    info->Get(vtkDataObject::ORIGIN(), origin);
  }
  std::ostringstream text;
  text << extent[1] - extent[0] + 1 << " x " << extent[3] - extent[2] + 1 << " x "
       << extent[5] - extent[4] + 1 << " voxels, spacing " << spacing[0] << " " << spacing[1]
       << " " << spacing[2] << ", origin " << origin[0] << " " << origin[1] << " " << origin[2];
  return text.str();
}

// "TIFF file 'x' is cut ... Nothing is read" -> "is cut ...": a step's refusal as a problem
// of the series (which names the file itself).
std::string stepProblem(const std::string& error, const std::string& stepName)
{
  std::string text = error;
  if (text.compare(0, stepName.size(), stepName) == 0)
  {
    text = text.substr(std::min(text.size(), stepName.size() + 1));
  }
  const std::string tail = ". Nothing is read";
  const std::size_t end = text.find(tail);
  return end == std::string::npos ? text : text.substr(0, end);
}
} // namespace

//------------------------------------------------------------------------------
void vtkCheckedTIFFReader::ClassifyList()
{
  this->Series = false;
  this->OneImageSet = false;
  const std::vector<std::string> files = this->Files();
  std::vector<mcv::TiffPage> pages;
  if (files.size() < 2 || !mcv::readTiffDirectories(files[0], pages).empty() || pages.empty())
  {
    return; // one file, or a first file whose problem the stack's checks report
  }
  if (mcv::isOMEDescription(pages[0].Description))
  {
    // The parts of one multi-file OME-TIFF, all selected (as the GUI's file dialog groups
    // them): the image of the first, which names the others.
    mcv::TiffPlaneMap map;
    const std::string base = vtksys::SystemTools::GetFilenameName(files[0]);
    if (mcv::parseOME(pages[0].Description, base, map).empty() && map.Files.size() > 1 &&
      std::all_of(files.begin(), files.end(), [&](const std::string& file) {
        return std::find(map.Files.begin(), map.Files.end(),
                 vtksys::SystemTools::GetFilenameName(file)) != map.Files.end();
      }))
    {
      this->OneImageSet = true;
      return;
    }
  }
  this->Series = pages.size() > 1;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkCheckedTIFFReader> vtkCheckedTIFFReader::StepReader(const std::string& file)
{
  auto step = vtkSmartPointer<vtkCheckedTIFFReader>::New();
  step->AddFileName(file.c_str());
  step->SetSpacingSpecifiedFlag(this->GetSpacingSpecifiedFlag());
  step->SetDataSpacing(this->GetDataSpacing());
  step->SetDataOrigin(this->GetDataOrigin());
  return step;
}

//------------------------------------------------------------------------------
std::string vtkCheckedTIFFReader::SeriesInformation(vtkInformation* outInfo)
{
  const std::vector<std::string> files = this->Files();
  vtkSmartPointer<vtkCheckedTIFFReader> first; // its information is the series'
  std::string firstGrid, firstContents;
  for (std::size_t i = 0; i < files.size(); ++i)
  {
    // Each file's header with every check of a single file (no data is read).
    vtkSmartPointer<vtkCheckedTIFFReader> step = this->StepReader(files[i]);
    std::ostringstream which;
    which << "has a file '" << files[i] << "' (time step " << i + 1 << ") that ";
    const std::string error = mcv::caughtErrors(step, [&] { step->UpdateInformation(); });
    if (!error.empty() || step->Refused)
    {
      return which.str() + stepProblem(error, step->Describe());
    }
    vtkInformation* info = step->GetOutputInformation(0);
    if (step->Frames() > 1)
    {
      return which.str() + "holds " + std::to_string(step->Frames()) +
        " frames, where a series of files takes one frame per file (open the file alone to "
        "see its frames as time steps)";
    }
    const std::string grid = gridOf(info);
    const std::string contents = step->Contents();
    if (i == 0)
    {
      first = step;
      firstGrid = grid;
      firstContents = contents;
    }
    else if (grid != firstGrid || contents != firstContents)
    {
      return which.str() + "holds " + grid + ", " + contents + ", but the first file '" +
        files[0] + "' holds " + firstGrid + ", " + firstContents +
        ": the files of a time series must share one grid and one set of channels";
    }
  }
  vtkInformation* info = first->GetOutputInformation(0);
  outInfo->CopyEntry(info, vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  outInfo->CopyEntry(info, vtkDataObject::SPACING());
  outInfo->CopyEntry(info, vtkDataObject::ORIGIN());
  outInfo->CopyEntry(info, vtkDataObject::POINT_DATA_VECTOR(), 1);
  outInfo->CopyEntry(info, vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT());
  std::vector<double> times(files.size());
  for (std::size_t i = 0; i < times.size(); ++i)
  {
    times[i] = static_cast<double>(i);
  }
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(),
    static_cast<int>(times.size()));
  const double range[2] = { times.front(), times.back() };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  return "";
}

//------------------------------------------------------------------------------
int vtkCheckedTIFFReader::ReadSeriesStep(vtkInformation* outInfo)
{
  // The step: the last whose time is at or before the requested time (as ParaView's
  // readers snap), the first before it.
  const std::vector<std::string> files = this->Files();
  std::size_t index = 0;
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    const double time = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    const double last = static_cast<double>(files.size() - 1);
    index = static_cast<std::size_t>(std::floor(std::min(std::max(time, 0.0), last) + 1e-9));
  }
  // A reader of its own for this read, dropped with its data once the output holds it: one
  // volume in memory, not one per step visited (and no reader's state left from another
  // read: vtkTIFFReader reads a multi-page file wrongly when it runs again).
  vtkSmartPointer<vtkCheckedTIFFReader> step = this->StepReader(files[index]);
  int extent[6];
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent);
  vtkImageData* output = vtkImageData::GetData(outInfo);
  if (extent[1] < extent[0] || extent[3] < extent[2] || extent[5] < extent[4])
  {
    output->Initialize(); // no piece for this process
    return 1;
  }
  const std::string error = mcv::caughtErrors(step, [&] { step->UpdateExtent(extent); });
  vtkImageData* read = step->GetOutput();
  if (!error.empty() || read->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro(<< "'" << this->Files()[index] << "' (time step " << index + 1 << ") "
                  << (error.empty() ? std::string("gave no data") : stepProblem(error, step->Describe())));
    return 0;
  }
  output->ShallowCopy(read);
  output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), static_cast<double>(index));
  return 1;
}
