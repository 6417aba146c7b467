#include "vtkCheckedNIFTIImageReader.h"

#include "CheckedReading.h"

#include "vtkNIFTIImageHeader.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkFieldData.h"

#include "../Common/mcvLabelTables.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <sstream>

vtkStandardNewMacro(vtkCheckedNIFTIImageReader);

namespace
{
bool endsWith(const std::string& s, const std::string& tail)
{
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The file that holds the voxels: the .nii itself, or the .img beside a .hdr.
std::string dataFileOf(const std::string& name)
{
  for (const char* hdr : { ".hdr", ".HDR" })
  {
    if (endsWith(name, hdr))
    {
      const std::string stem = name.substr(0, name.size() - 4);
      for (const char* img : { ".img", ".IMG", ".img.gz", ".IMG.gz" })
      {
        if (std::ifstream(stem + img).good())
        {
          return stem + img;
        }
      }
    }
  }
  return name;
}

} // namespace

//------------------------------------------------------------------------------
std::string vtkCheckedNIFTIImageReader::CheckHeaderAgainstFile()
{
  vtkNIFTIImageHeader* header = this->GetNIFTIHeader();
  if (!header)
  {
    return "has no readable NIfTI header";
  }
  std::ostringstream msg;
  const vtkTypeInt64 rank = header->GetDim(0);
  if (rank < 1 || rank > 5)
  {
    msg << "has " << rank << " dimensions in its header; 1 to 5 (x, y, z, time, components) "
        << "can be read";
    return msg.str();
  }
  // Bytes the header promises: every dimension it declares, as stored.
  double voxels = 1;
  for (int i = 1; i <= rank; ++i)
  {
    if (header->GetDim(i) < 1)
    {
      msg << "has dimension " << i << " = " << header->GetDim(i) << " in its header (must be >= 1)";
      return msg.str();
    }
    voxels *= static_cast<double>(header->GetDim(i));
  }
  double spacing[3] = { 1, 1, 1 };
  for (int i = 1; i <= std::min<vtkTypeInt64>(rank, 3); ++i)
  {
    spacing[i - 1] = header->GetPixDim(i);
  }
  std::string problem = mcv::checkSpacing(spacing, 3, "pixdim in its header");
  if (!problem.empty())
  {
    return problem;
  }
  const int bitsPerVoxel = header->GetBitPix();
  if (bitsPerVoxel <= 0 || bitsPerVoxel % 8 != 0)
  {
    msg << "has " << bitsPerVoxel << " bits per voxel (datatype " << header->GetDataType()
        << "), which cannot be read";
    return msg.str();
  }
  const std::string dataFile = dataFileOf(this->GetFileName() ? this->GetFileName() : "");
  const bool single = dataFile == this->GetFileName();
  const double offset = single ? static_cast<double>(header->GetVoxOffset()) : 0.0;

  // The file before the memory: a header of 32767^3 over a small file is a truncated file,
  // not a request for 128 TiB. Counting does not allocate the volume.
  std::string error;
  const std::int64_t present =
    mcv::inflatedBytes(dataFile, 0, mcv::Compression::GzipOrPlain, error);
  if (present < 0)
  {
    return (single ? "" : "has a data file '" + dataFile + "' that ") + error;
  }
  const bool gzipped = endsWith(dataFile, ".gz") || endsWith(dataFile, ".GZ");
  problem = mcv::checkPresent(voxels, bitsPerVoxel / 8, offset, present,
    (single ? std::string("the file") : "its data file '" + dataFile + "'") +
      (gzipped ? " holds, once decompressed," : " holds"));
  return problem.empty() ? mcv::checkFitsInMemory(voxels, bitsPerVoxel / 8) : problem;
}

//------------------------------------------------------------------------------
int vtkCheckedNIFTIImageReader::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The header is parsed by the superclass; the checks then compare it with the file.
  this->Refused = !mcv::checkedRequestInformation(this, outputVector, this->Describe(), [&] {
    return this->Superclass::RequestInformation(request, inputVector, outputVector)
      ? this->CheckHeaderAgainstFile()
      : std::string("cannot be read");
  });
  return this->Refused ? 0 : 1;
}

//------------------------------------------------------------------------------
int vtkCheckedNIFTIImageReader::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  const int ok = mcv::checkedSeriesRequestData(this, outputVector, this->Describe(), this->Refused,
    [&] { return this->Superclass::RequestData(request, inputVector, outputVector); });
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  vtkDataArray* scalars = output ? output->GetPointData()->GetScalars() : nullptr;
  const std::string labels =
    ok && scalars && scalars->GetName() && this->GetFileName()
    ? mcv::vtkhelpers::labelFileBeside(this->GetFileName())
    : std::string();
  if (!labels.empty())
  {
    // An atlas: the names of its values (mcvLabelTables.h). A bad table is said, and the
    // volume is still read.
    std::string error;
    if (auto table = mcv::vtkhelpers::readLabelFile(labels, scalars->GetName(), error))
    {
      output->GetFieldData()->AddArray(table);
    }
    else
    {
      vtkWarningMacro(<< this->Describe() << ": " << error << "; its values stay unnamed.");
    }
  }
  return ok;
}

//------------------------------------------------------------------------------
std::string vtkCheckedNIFTIImageReader::Describe()
{
  return std::string("NIfTI file '") + (this->GetFileName() ? this->GetFileName() : "") + "'";
}
