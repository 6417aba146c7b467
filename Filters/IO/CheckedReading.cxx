#include "CheckedReading.h"

#include "MemoryBudget.h" // mcv core (Filters/Core/common): the memory this process may use

#include "../Common/mcvFileNames.h" // fileStem, seriesStem

#include "vtkAlgorithm.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkFileSeriesReader.h"
#include "vtkImageReader2.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkImageData.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtk_zlib.h"
#include "vtksys/FStream.hxx"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

namespace mcv
{
namespace
{
// Collects the errors that an object reports while it lives, the first three joined by "; "
// (an observer of ErrorEvent: VTK then hands the messages to it instead of printing them).
class ReportedErrors
{
public:
  explicit ReportedErrors(vtkObject* object)
    : Object(object)
  {
    vtkNew<vtkCallbackCommand> callback;
    callback->SetClientData(this);
    callback->SetCallback(&ReportedErrors::OnError);
    this->Tag = object->AddObserver(vtkCommand::ErrorEvent, callback);
  }
  ~ReportedErrors() { this->Object->RemoveObserver(this->Tag); }
  ReportedErrors(const ReportedErrors&) = delete;
  void operator=(const ReportedErrors&) = delete;

  std::string Text;

private:
  // "ERROR: In file, line N\nClass (0x...): message\n\n" -> "message" (no final full stop).
  static void OnError(vtkObject*, unsigned long, void* clientData, void* callData)
  {
    auto* self = static_cast<ReportedErrors*>(clientData);
    if (++self->Count > 3 || !callData)
    {
      return;
    }
    std::string text = static_cast<const char*>(callData);
    const std::size_t start = text.find("): ");
    if (start != std::string::npos)
    {
      text = text.substr(start + 3);
    }
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '.'))
    {
      text.pop_back();
    }
    self->Text += (self->Text.empty() ? "" : "; ") + text;
  }

  vtkObject* Object;
  unsigned long Tag = 0;
  int Count = 0;
};

void refuse(vtkAlgorithm* reader, vtkInformationVector* outputVector, const std::string& what,
  const std::string& problem)
{
  if (vtkImageData* image = vtkImageData::GetData(outputVector))
  {
    image->Initialize(); // no zero-filled volume, and none left from an earlier file
  }
  vtkErrorWithObjectMacro(reader, << what << " " << problem << ". Nothing is read.");
}

bool isGzip(const unsigned char* p)
{
  return p[0] == 0x1f && p[1] == 0x8b;
}

bool isZlib(const unsigned char* p)
{
  return (p[0] & 0x0f) == 8 && ((p[0] << 8) | p[1]) % 31 == 0;
}
} // namespace

//------------------------------------------------------------------------------
std::int64_t fileBytes(const std::string& name)
{
  vtksys::ifstream in(name.c_str(), std::ios::in | std::ios::binary);
  if (!in)
  {
    return -1;
  }
  in.seekg(0, std::ios::end);
  return static_cast<std::int64_t>(in.tellg());
}

//------------------------------------------------------------------------------
std::int64_t inflatedBytes(
  const std::string& name, std::int64_t offset, Compression expected, std::string& error)
{
  vtksys::ifstream in(name.c_str(), std::ios::in | std::ios::binary);
  if (!in || !in.seekg(offset))
  {
    error = "cannot be opened";
    return -1;
  }
  std::vector<unsigned char> input(1 << 20);
  std::vector<unsigned char> output(1 << 20);
  // Refills the input after the `keep` bytes not yet consumed; false at the end of the file.
  auto refill = [&](z_stream& zs) {
    const std::size_t keep = zs.avail_in;
    std::copy(zs.next_in, zs.next_in + keep, input.begin());
    in.read(reinterpret_cast<char*>(input.data() + keep),
      static_cast<std::streamsize>(input.size() - keep));
    zs.next_in = input.data();
    zs.avail_in = static_cast<uInt>(keep + static_cast<std::size_t>(in.gcount()));
    return zs.avail_in > keep;
  };
  z_stream zs{};
  zs.next_in = input.data();
  refill(zs);
  const bool gzip = zs.avail_in >= 2 && isGzip(zs.next_in);
  const bool zlib = zs.avail_in >= 2 && isZlib(zs.next_in);
  if (expected == Compression::GzipOrPlain && !gzip)
  {
    return std::max<std::int64_t>(0, fileBytes(name) - offset);
  }
  if (!gzip && !zlib)
  {
    error = "holds no zlib or gzip stream at byte " + std::to_string(offset);
    return -1;
  }
  const std::string kind = gzip ? "gzip" : "zlib";
  if (inflateInit2(&zs, 15 + 32) != Z_OK) // 15 + 32: a gzip or a zlib header
  {
    error = "cannot be decompressed (zlib could not start)";
    return -1;
  }
  std::int64_t total = 0;
  std::string problem;
  for (;;)
  {
    if (zs.avail_in == 0 && !refill(zs))
    {
      problem = "the stream ends early";
      break;
    }
    zs.next_out = output.data();
    zs.avail_out = static_cast<uInt>(output.size());
    const int code = inflate(&zs, Z_NO_FLUSH);
    total += static_cast<std::int64_t>(output.size() - zs.avail_out);
    if (code == Z_STREAM_END)
    {
      // Another gzip member may follow (gzread reads on); anything else is ignored.
      if (zs.avail_in < 2)
      {
        refill(zs);
      }
      if (gzip && zs.avail_in >= 2 && isGzip(zs.next_in))
      {
        inflateReset(&zs);
        continue;
      }
      break;
    }
    if (code != Z_OK && code != Z_BUF_ERROR)
    {
      problem = zs.msg ? zs.msg : "corrupt data";
      break;
    }
  }
  inflateEnd(&zs);
  if (!problem.empty())
  {
    error = "is not a complete " + kind + " stream (" + problem + " after " +
      std::to_string(total) + " decompressed bytes)";
    return -1;
  }
  return total;
}

//------------------------------------------------------------------------------
std::string checkSpacing(const double* spacing, int n, const std::string& field)
{
  for (int i = 0; i < n; ++i)
  {
    if (!std::isfinite(spacing[i]) || spacing[i] == 0)
    {
      std::ostringstream msg;
      msg << "has spacing " << spacing[i] << " along axis " << i + 1 << " (" << field
          << " must be finite and non-zero)";
      return msg.str();
    }
  }
  return "";
}

//------------------------------------------------------------------------------
std::string checkPresent(double voxels, double bytesPerVoxel, double offset, std::int64_t present,
  const std::string& holder)
{
  const double promised = offset + voxels * bytesPerVoxel;
  if (static_cast<double>(present) >= promised)
  {
    return "";
  }
  std::ostringstream msg;
  msg << std::fixed << std::setprecision(0) << "is truncated: its header promises " << promised
      << " bytes (" << voxels << " voxels of " << bytesPerVoxel
      << (bytesPerVoxel == 1 ? " byte" : " bytes") << " from offset " << offset << "), "
      << holder << " " << present;
  return msg.str();
}

//------------------------------------------------------------------------------
std::string checkFitsInMemory(double voxels, double bytesPerVoxel)
{
  const double bytes = voxels * bytesPerVoxel;
  const std::size_t available = availableMemoryBytes();
  if (bytes <= static_cast<double>(available))
  {
    return "";
  }
  const double largest = static_cast<double>(std::numeric_limits<std::size_t>::max());
  std::ostringstream msg;
  msg << std::fixed << std::setprecision(0) << "needs "
      << formatBytes(static_cast<std::size_t>(std::min(bytes, largest)), true) << " for its "
      << voxels << " voxels, but only " << formatBytes(available) << " is available";
  return msg.str();
}

//------------------------------------------------------------------------------
int checkedRequestInformation(vtkAlgorithm* reader, vtkInformationVector* outputVector,
  const std::string& what, const std::function<std::string()>& readHeader)
{
  std::string problem;
  {
    ReportedErrors errors(reader);
    problem = readHeader();
    // The reader's own error says more than "cannot be read".
    if (!errors.Text.empty() && (problem.empty() || problem == "cannot be read"))
    {
      problem = "cannot be read (" + errors.Text + ")";
    }
  }
  if (problem.empty())
  {
    return 1;
  }
  refuse(reader, outputVector, what, problem);
  return 0;
}

//------------------------------------------------------------------------------
std::string caughtErrors(vtkObject* object, const std::function<void()>& run)
{
  ReportedErrors errors(object);
  run();
  return errors.Text;
}

//------------------------------------------------------------------------------
int checkedRequestData(vtkAlgorithm* reader, vtkInformationVector* outputVector,
  const std::string& what, bool refused, const std::function<int()>& readData)
{
  if (refused)
  {
    if (vtkImageData* image = vtkImageData::GetData(outputVector))
    {
      image->Initialize();
    }
    return 0;
  }
  std::string error;
  int ok = 0;
  {
    ReportedErrors errors(reader);
    ok = readData();
    error = errors.Text;
  }
  if (ok && error.empty())
  {
    return 1;
  }
  refuse(reader, outputVector, what,
    "could not be read whole" + (error.empty() ? std::string() : " (" + error + ")"));
  return 0;
}

//------------------------------------------------------------------------------
std::string checkSeriesGrid(vtkImageReader2* reader, vtkInformation* outInfo)
{
  if (!outInfo || !outInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    return "";
  }
  int announced[6];
  outInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), announced);
  double spacing[3] = { 1, 1, 1 }, origin[3] = { 0, 0, 0 };
  if (outInfo->Has(vtkDataObject::SPACING()))
  {
    outInfo->Get(vtkDataObject::SPACING(), spacing);
  }
  if (outInfo->Has(vtkDataObject::ORIGIN()))
  {
    outInfo->Get(vtkDataObject::ORIGIN(), origin);
  }
  int type = reader->GetDataScalarType();
  int components = reader->GetNumberOfScalarComponents();
  if (vtkInformation* scalars = vtkDataObject::GetActiveFieldInformation(
        outInfo, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS))
  {
    type = scalars->Has(vtkDataObject::FIELD_ARRAY_TYPE())
      ? scalars->Get(vtkDataObject::FIELD_ARRAY_TYPE())
      : type;
    components = scalars->Has(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS())
      ? scalars->Get(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS())
      : components;
  }
  const int* extent = reader->GetDataExtent();
  const double* ownSpacing = reader->GetDataSpacing();
  const double* ownOrigin = reader->GetDataOrigin();
  bool same = type == reader->GetDataScalarType() &&
    components == reader->GetNumberOfScalarComponents();
  for (int i = 0; i < 6; ++i)
  {
    same = same && extent[i] == announced[i];
  }
  for (int i = 0; i < 3; ++i)
  {
    // Spacing and origin as the header gives them: the same header field gives the same
    // double, so any difference is a different grid.
    same = same && ownSpacing[i] == spacing[i] && ownOrigin[i] == origin[i];
  }
  if (same)
  {
    return "";
  }
  auto grid = [](const int* e, const double* s, const double* o, int t, int c) {
    std::ostringstream os;
    os << e[1] - e[0] + 1 << " x " << e[3] - e[2] + 1 << " x " << e[5] - e[4] + 1
       << " voxels, spacing " << s[0] << " " << s[1] << " " << s[2] << ", origin " << o[0] << " "
       << o[1] << " " << o[2] << ", " << vtkImageScalarTypeNameMacro(t) << " x " << c;
    return os.str();
  };
  const char* first = outInfo->Has(vtkFileSeriesReader::FILE_SERIES_FIRST_FILENAME())
    ? outInfo->Get(vtkFileSeriesReader::FILE_SERIES_FIRST_FILENAME())
    : nullptr;
  return "has " +
    grid(extent, ownSpacing, ownOrigin, reader->GetDataScalarType(),
      reader->GetNumberOfScalarComponents()) +
    ", but the first file of its time series" + (first ? " '" + std::string(first) + "'" : "") +
    " has " + grid(announced, spacing, origin, type, components) +
    ": the files of a time series must share one grid (resample them onto one grid, or open "
    "them one by one)";
}

//------------------------------------------------------------------------------
std::string channelArrayName(vtkInformation* outInfo, const std::string& fileName)
{
  if (outInfo && outInfo->Has(vtkFileSeriesReader::FILE_SERIES_NUMBER_OF_FILES()) &&
    outInfo->Get(vtkFileSeriesReader::FILE_SERIES_NUMBER_OF_FILES()) > 1 &&
    outInfo->Has(vtkFileSeriesReader::FILE_SERIES_FIRST_FILENAME()) &&
    outInfo->Get(vtkFileSeriesReader::FILE_SERIES_FIRST_FILENAME()))
  {
    return seriesStem(outInfo->Get(vtkFileSeriesReader::FILE_SERIES_FIRST_FILENAME()));
  }
  return fileStem(fileName);
}

//------------------------------------------------------------------------------
void nameScalars(vtkInformationVector* outputVector, const std::string& name)
{
  vtkImageData* image = vtkImageData::GetData(outputVector);
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  if (scalars && !name.empty())
  {
    scalars->SetName(name.c_str());
  }
}

//------------------------------------------------------------------------------
int checkedSeriesRequestData(vtkImageReader2* reader, vtkInformationVector* outputVector,
  const std::string& what, bool refused, const std::function<int()>& readData)
{
  // In a time series this file's header was read for this step (vtkFileSeriesReader asks
  // for the information of the step's file first); the output is on the first file's grid.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const std::string problem = refused ? "" : checkSeriesGrid(reader, outInfo);
  if (!problem.empty())
  {
    refuse(reader, outputVector, what, problem);
    return 0;
  }
  const int read = checkedRequestData(reader, outputVector, what, refused, readData);
  if (read)
  {
    // The channel's name is its file's (a reader's generic name says nothing about it).
    nameScalars(outputVector,
      channelArrayName(outInfo, reader->GetFileName() ? reader->GetFileName() : ""));
  }
  return read;
}

} // namespace mcv
