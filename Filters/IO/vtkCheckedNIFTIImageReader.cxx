#include "vtkCheckedNIFTIImageReader.h"

#include "MemoryBudget.h" // mcv core (Filters/Core/common): the memory this process may use

#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNIFTIImageHeader.h"
#include "vtkObjectFactory.h"
#include "vtk_zlib.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <vector>

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

// Bytes of the file once decompressed (plain files: their size); -1 with `error` set when
// the gzip stream is corrupt or ends early. Reading the whole stream is the only way to
// know: a truncated stream has no trailer to trust.
std::int64_t uncompressedBytes(const std::string& name, std::string& error)
{
  gzFile file = gzopen(name.c_str(), "rb");
  if (!file)
  {
    error = "cannot be opened";
    return -1;
  }
  std::vector<char> buffer(1 << 20);
  std::int64_t total = 0;
  int n = 0;
  while ((n = gzread(file, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0)
  {
    total += n;
  }
  int code = Z_OK;
  const char* message = gzerror(file, &code);
  if (n < 0 || (code != Z_OK && code != Z_STREAM_END))
  {
    error = std::string("is not a complete gzip stream (") + (message ? message : "error") +
      " after " + std::to_string(total) + " decompressed bytes)";
    gzclose(file);
    return -1;
  }
  gzclose(file);
  return total;
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
  for (int i = 1; i <= std::min<vtkTypeInt64>(rank, 3); ++i)
  {
    const double spacing = header->GetPixDim(i);
    if (!std::isfinite(spacing) || spacing == 0)
    {
      msg << "has spacing " << spacing << " along axis " << i
          << " in its header (pixdim must be finite and non-zero)";
      return msg.str();
    }
  }
  const int bitsPerVoxel = header->GetBitPix();
  if (bitsPerVoxel <= 0 || bitsPerVoxel % 8 != 0)
  {
    msg << "has " << bitsPerVoxel << " bits per voxel (datatype " << header->GetDataType()
        << "), which cannot be read";
    return msg.str();
  }
  const double dataBytes = voxels * (bitsPerVoxel / 8);
  const std::string dataFile = dataFileOf(this->GetFileName() ? this->GetFileName() : "");
  const double offset =
    dataFile == this->GetFileName() ? static_cast<double>(header->GetVoxOffset()) : 0.0;

  // Memory first: a header of 32767^3 must not get as far as the allocation.
  const double available = static_cast<double>(mcv::availableMemoryBytes());
  if (dataBytes > available)
  {
    msg.precision(3);
    msg << "needs " << dataBytes / double(1 << 30) << " GiB for its "
        << static_cast<std::int64_t>(voxels) << " voxels, but only "
        << available / double(1 << 30) << " GiB is available";
    return msg.str();
  }
  std::string error;
  const std::int64_t present = uncompressedBytes(dataFile, error);
  if (present < 0)
  {
    return (dataFile == this->GetFileName() ? "" : "its data file '" + dataFile + "' ") + error;
  }
  if (static_cast<double>(present) < offset + dataBytes)
  {
    msg << "is truncated: its header promises " << static_cast<std::int64_t>(offset + dataBytes)
        << " bytes (" << static_cast<std::int64_t>(voxels) << " voxels of " << bitsPerVoxel / 8
        << " bytes from offset " << static_cast<std::int64_t>(offset) << "), the file holds "
        << present;
    return msg.str();
  }
  return "";
}

//------------------------------------------------------------------------------
int vtkCheckedNIFTIImageReader::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->Refused = true;
  if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
  {
    return 0;
  }
  const std::string problem = this->CheckHeaderAgainstFile();
  if (!problem.empty())
  {
    vtkErrorMacro(<< "NIfTI file '" << (this->GetFileName() ? this->GetFileName() : "")
                  << "' " << problem << ". Nothing is read.");
    return 0;
  }
  this->Refused = false;
  return 1;
}

//------------------------------------------------------------------------------
int vtkCheckedNIFTIImageReader::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (this->Refused)
  {
    vtkImageData::GetData(outputVector)->Initialize(); // no zero-filled or stale volume
    return 0;
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}
