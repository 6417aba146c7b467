#include "vtkVolPackDenReader.h"

#include "CheckedReading.h"

#include "vtkDataObject.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtksys/FStream.hxx"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>

vtkStandardNewMacro(vtkVolPackDenReader);

namespace
{
constexpr std::size_t HeaderBytes = 62; // 29 int16 fields + one int32

struct DenHeader
{
  int dims[3] = { 0, 0, 0 };
  std::uint64_t voxels = 0;
  std::uint64_t fileSize = 0;
};

std::uint16_t u16(const unsigned char* p, bool swap)
{
  // Header fields are in the writer's native order; version 1 tells which it was.
  const std::uint16_t le = static_cast<std::uint16_t>(p[0] | (p[1] << 8));
  const std::uint16_t be = static_cast<std::uint16_t>((p[0] << 8) | p[1]);
  return swap ? be : le;
}

std::uint32_t u32(const unsigned char* p, bool swap)
{
  const std::uint32_t le = static_cast<std::uint32_t>(p[0]) |
    (static_cast<std::uint32_t>(p[1]) << 8) | (static_cast<std::uint32_t>(p[2]) << 16) |
    (static_cast<std::uint32_t>(p[3]) << 24);
  const std::uint32_t be = static_cast<std::uint32_t>(p[3]) |
    (static_cast<std::uint32_t>(p[2]) << 8) | (static_cast<std::uint32_t>(p[1]) << 16) |
    (static_cast<std::uint32_t>(p[0]) << 24);
  return swap ? be : le;
}

// Returns an empty string on success, else what is wrong with the file.
std::string readHeader(const char* fileName, DenHeader& header)
{
  if (!fileName || !*fileName)
  {
    return "no file name was given";
  }
  vtksys::ifstream in(fileName, std::ios::in | std::ios::binary);
  if (!in)
  {
    return std::string("cannot open '") + fileName + "'";
  }
  in.seekg(0, std::ios::end);
  header.fileSize = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0, std::ios::beg);
  unsigned char raw[HeaderBytes];
  if (header.fileSize < HeaderBytes || !in.read(reinterpret_cast<char*>(raw), HeaderBytes))
  {
    return std::string("'") + fileName + "' is too short for a VolPack .den header (" +
      std::to_string(header.fileSize) + " bytes)";
  }
  // Little-endian reading of the version: 1 (as written on a little-endian machine)
  // or 0x0100 (written big-endian: swap every field).
  const std::uint16_t version = static_cast<std::uint16_t>(raw[0] | (raw[1] << 8));
  bool swap = false;
  if (version == 1)
  {
    swap = false;
  }
  else if (version == 0x0100)
  {
    swap = true;
  }
  else
  {
    return std::string("'") + fileName + "' is not a VolPack .den file (version field " +
      std::to_string(version) + ", expected 1)";
  }
  // Field order: version, orig_min[3], orig_max[3], orig_len[3], extr_min[3], extr_max[3],
  // extr_len[3], map_min[3], map_max[3], map_len[3], map_warps, map_length (int32).
  const int mapLenField = 1 + 8 * 3; // index of map_len[0] among the int16 fields
  for (int a = 0; a < 3; ++a)
  {
    header.dims[a] = static_cast<std::int16_t>(u16(raw + 2 * (mapLenField + a), swap));
  }
  const std::uint32_t length = u32(raw + 58, swap);
  if (header.dims[0] <= 0 || header.dims[1] <= 0 || header.dims[2] <= 0)
  {
    return std::string("'") + fileName + "' has invalid dimensions " +
      std::to_string(header.dims[0]) + " x " + std::to_string(header.dims[1]) + " x " +
      std::to_string(header.dims[2]);
  }
  header.voxels = static_cast<std::uint64_t>(header.dims[0]) * header.dims[1] * header.dims[2];
  if (header.voxels != length)
  {
    return std::string("'") + fileName + "' has an inconsistent header (" +
      std::to_string(header.dims[0]) + " x " + std::to_string(header.dims[1]) + " x " +
      std::to_string(header.dims[2]) + " voxels but a length of " + std::to_string(length) + ")";
  }
  if (header.fileSize < HeaderBytes + header.voxels)
  {
    return std::string("'") + fileName + "' is truncated: " +
      std::to_string(header.fileSize - HeaderBytes) + " data bytes for " +
      std::to_string(header.voxels) + " voxels";
  }
  return std::string();
}
} // namespace

//------------------------------------------------------------------------------
vtkVolPackDenReader::vtkVolPackDenReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
  this->SetScalarArrayName("Density");
}

//------------------------------------------------------------------------------
vtkVolPackDenReader::~vtkVolPackDenReader()
{
  this->SetFileName(nullptr);
  this->SetScalarArrayName(nullptr);
}

//------------------------------------------------------------------------------
int vtkVolPackDenReader::CanReadFile(const char* fileName)
{
  // The version field says whether this is a .den file. Whether it is whole is for
  // RequestInformation to say, with the reason: refused here, a truncated file would only
  // get ParaView's "no reader found".
  unsigned char version[2];
  vtksys::ifstream in(fileName ? fileName : "", std::ios::in | std::ios::binary);
  if (!fileName || !in.read(reinterpret_cast<char*>(version), 2))
  {
    return 0;
  }
  return (version[0] == 1 && version[1] == 0) || (version[0] == 0 && version[1] == 1) ? 1 : 0;
}

//------------------------------------------------------------------------------
bool vtkVolPackDenReader::CheckSpacing()
{
  // The format stores no spacing: a bad one can only come from the property.
  const std::string problem =
    mcv::checkSpacing(this->DataSpacing, 3, "the DataSpacing property");
  if (!problem.empty())
  {
    vtkErrorMacro("'" << this->FileName << "' " << problem << ".");
  }
  return problem.empty();
}

//------------------------------------------------------------------------------
int vtkVolPackDenReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  DenHeader header;
  const std::string problem = readHeader(this->FileName, header);
  if (!problem.empty())
  {
    vtkErrorMacro(<< problem << ".");
    return 0;
  }
  for (int a = 0; a < 3; ++a)
  {
    this->Dimensions[a] = header.dims[a];
  }
  const std::uint64_t trailing = header.fileSize - HeaderBytes - header.voxels;
  if (trailing > 0)
  {
    // A consistent header over more data than it describes: read what it says, but say so
    // (a header from another volume would otherwise go unnoticed).
    vtkWarningMacro("'" << this->FileName << "' holds " << trailing
                        << " bytes after the " << header.dims[0] << " x " << header.dims[1]
                        << " x " << header.dims[2]
                        << " voxels its header describes: they are not read.");
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int extent[6] = { 0, header.dims[0] - 1, 0, header.dims[1] - 1, 0, header.dims[2] - 1 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), this->DataSpacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), this->DataOrigin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_UNSIGNED_CHAR, 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkVolPackDenReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  DenHeader header;
  const std::string problem = readHeader(this->FileName, header);
  if (!problem.empty())
  {
    vtkErrorMacro(<< problem << ".");
    return 0;
  }
  if (!this->CheckSpacing())
  {
    output->Initialize();
    return 0;
  }
  vtksys::ifstream in(this->FileName, std::ios::in | std::ios::binary);
  in.seekg(static_cast<std::streamoff>(HeaderBytes), std::ios::beg);

  vtkNew<vtkUnsignedCharArray> density;
  density->SetName(this->ScalarArrayName && *this->ScalarArrayName ? this->ScalarArrayName
                                                                   : "Density");
  density->SetNumberOfTuples(static_cast<vtkIdType>(header.voxels));
  // Read in slabs so that progress is reported on large files.
  const std::uint64_t chunk = std::uint64_t(1) << 22;
  char* dst = reinterpret_cast<char*>(density->GetPointer(0));
  for (std::uint64_t done = 0; done < header.voxels;)
  {
    const std::uint64_t n = std::min(chunk, header.voxels - done);
    if (!in.read(dst + done, static_cast<std::streamsize>(n)))
    {
      vtkErrorMacro("Read failed on '" << this->FileName << "' after " << done << " of "
                                       << header.voxels << " voxels.");
      return 0;
    }
    done += n;
    this->UpdateProgress(static_cast<double>(done) / static_cast<double>(header.voxels));
  }

  output->SetExtent(0, header.dims[0] - 1, 0, header.dims[1] - 1, 0, header.dims[2] - 1);
  output->SetSpacing(this->DataSpacing);
  output->SetOrigin(this->DataOrigin);
  output->GetPointData()->SetScalars(density);
  return 1;
}

//------------------------------------------------------------------------------
void vtkVolPackDenReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ScalarArrayName: " << (this->ScalarArrayName ? this->ScalarArrayName : "")
     << "\n";
  os << indent << "DataSpacing: " << this->DataSpacing[0] << " " << this->DataSpacing[1] << " "
     << this->DataSpacing[2] << "\n";
  os << indent << "DataOrigin: " << this->DataOrigin[0] << " " << this->DataOrigin[1] << " "
     << this->DataOrigin[2] << "\n";
  os << indent << "Dimensions: " << this->Dimensions[0] << " " << this->Dimensions[1] << " "
     << this->Dimensions[2] << "\n";
}
