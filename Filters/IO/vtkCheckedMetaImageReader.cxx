#include "vtkCheckedMetaImageReader.h"

#include "CheckedReading.h"

#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtksys/FStream.hxx"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkCheckedMetaImageReader);

namespace
{
// The header as "Key = Value" pairs, up to and including ElementDataFile (the last field:
// in a .mha the voxels follow its line). `dataOffset` is where that line ends; `listed` the
// lines after "ElementDataFile = LIST", one data file each.
struct MetaHeader
{
  std::map<std::string, std::string> fields;
  std::int64_t dataOffset = 0;
  std::vector<std::string> listed;
};

std::string trim(const std::string& s)
{
  const std::size_t a = s.find_first_not_of(" \t\r\n");
  const std::size_t b = s.find_last_not_of(" \t\r\n");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// "" on success, else what is wrong. Random bytes named .mhd end here (no ElementDataFile).
std::string readHeader(const std::string& name, MetaHeader& header)
{
  vtksys::ifstream in(name.c_str(), std::ios::in | std::ios::binary);
  if (!in)
  {
    return "cannot be opened";
  }
  std::string line;
  while (header.dataOffset < (1 << 20) && std::getline(in, line))
  {
    header.dataOffset += static_cast<std::int64_t>(line.size()) + 1;
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos || line.find('\0') != std::string::npos)
    {
      if (trim(line).empty())
      {
        continue;
      }
      break; // not a header line: not a MetaImage header (or a broken one)
    }
    const std::string key = trim(line.substr(0, eq));
    header.fields[key] = trim(line.substr(eq + 1));
    if (key == "ElementDataFile")
    {
      if (header.fields[key].compare(0, 4, "LIST") == 0)
      {
        while (std::getline(in, line))
        {
          if (!trim(line).empty())
          {
            header.listed.push_back(trim(line));
          }
        }
      }
      return "";
    }
  }
  return "has no MetaImage header (no 'ElementDataFile = ...' line in its first lines)";
}

// Numbers of a field: false when one is not a number (strtod reads "nan" and "inf").
bool numbers(const std::string& text, std::vector<double>& values)
{
  std::istringstream words(text);
  std::string word;
  while (words >> word)
  {
    char* end = nullptr;
    values.push_back(std::strtod(word.c_str(), &end));
    if (*end != '\0')
    {
      return false;
    }
  }
  return true;
}

// Bytes of one element of the types vtkMetaImageReader reads; 0 for any other type.
int elementBytes(std::string type)
{
  const std::string array = "_ARRAY";
  if (type.size() > array.size() && type.compare(type.size() - array.size(), array.size(), array) == 0)
  {
    type.resize(type.size() - array.size());
  }
  static const std::map<std::string, int> sizes = { { "MET_CHAR", 1 }, { "MET_UCHAR", 1 },
    { "MET_SHORT", 2 }, { "MET_USHORT", 2 }, { "MET_INT", 4 }, { "MET_UINT", 4 },
    { "MET_LONG", 4 }, { "MET_ULONG", 4 }, { "MET_LONG_LONG", 8 }, { "MET_ULONG_LONG", 8 },
    { "MET_FLOAT", 4 }, { "MET_DOUBLE", 8 } };
  const auto found = sizes.find(type);
  return found == sizes.end() ? 0 : found->second;
}

bool isTrue(const std::string& value)
{
  return value == "True" || value == "true" || value == "TRUE" || value == "1";
}

// The data files: the header itself (LOCAL), one file, the LIST, or a printf pattern with
// its first, last and step numbers ("slice%03d.raw 1 84 1"); relative to the header's folder.
std::string dataFiles(const std::string& name, const MetaHeader& header,
  std::vector<std::string>& files)
{
  const std::string& value = header.fields.at("ElementDataFile");
  const std::string folder = vtksys::SystemTools::GetFilenamePath(name);
  auto resolve = [&](const std::string& file) {
    return vtksys::SystemTools::FileIsFullPath(file) || folder.empty() ? file
                                                                        : folder + "/" + file;
  };
  if (value == "LOCAL")
  {
    files.push_back(name);
  }
  else if (value.compare(0, 4, "LIST") == 0)
  {
    for (const std::string& file : header.listed)
    {
      files.push_back(resolve(file));
    }
  }
  else if (value.find('%') != std::string::npos)
  {
    std::istringstream words(value);
    std::string pattern;
    long first = 0, last = -1, step = 1;
    words >> pattern >> first >> last >> step;
    if (step <= 0 || last < first || (last - first) / step > 1000000)
    {
      return "has an ElementDataFile pattern '" + value + "' without a valid range";
    }
    for (long i = first; i <= last; i += step)
    {
      char buffer[4096];
      std::snprintf(buffer, sizeof(buffer), pattern.c_str(), static_cast<int>(i));
      files.push_back(resolve(buffer));
    }
  }
  else
  {
    files.push_back(resolve(value));
  }
  return files.empty() ? "lists no data file (ElementDataFile = " + value + ")" : "";
}
} // namespace

//------------------------------------------------------------------------------
std::string vtkCheckedMetaImageReader::CheckHeaderAgainstFile()
{
  const std::string name = this->GetFileName() ? this->GetFileName() : "";
  MetaHeader header;
  std::string problem = readHeader(name, header);
  if (!problem.empty())
  {
    return problem;
  }
  auto field = [&](const char* key) {
    const auto found = header.fields.find(key);
    return found == header.fields.end() ? std::string() : found->second;
  };
  std::ostringstream msg;
  std::vector<double> values;
  if (!numbers(field("NDims"), values) || values.size() != 1 || values[0] < 1 || values[0] > 3 ||
    values[0] != std::floor(values[0]))
  {
    return "has NDims = '" + field("NDims") + "' in its header; 1 to 3 dimensions can be read";
  }
  const int rank = static_cast<int>(values[0]);
  std::vector<double> dims;
  if (!numbers(field("DimSize"), dims) || static_cast<int>(dims.size()) != rank)
  {
    msg << "has DimSize = '" << field("DimSize") << "' in its header (" << rank
        << " whole numbers expected)";
    return msg.str();
  }
  double voxels = 1;
  for (int i = 0; i < rank; ++i)
  {
    if (!(dims[i] >= 1) || dims[i] != std::floor(dims[i]))
    {
      msg << "has dimension " << i + 1 << " = " << dims[i] << " in its header (DimSize must be "
          << "whole numbers >= 1)";
      return msg.str();
    }
    voxels *= dims[i];
  }
  // ElementSpacing, else ElementSize (as metaio reads them), else 1.
  const char* spacingKey = field("ElementSpacing").empty() ? "ElementSize" : "ElementSpacing";
  std::vector<double> spacing;
  if (!numbers(field(spacingKey), spacing))
  {
    return "has " + std::string(spacingKey) + " = '" + field(spacingKey) +
      "' in its header (numbers expected)";
  }
  spacing.resize(rank, 1.0);
  problem = mcv::checkSpacing(spacing.data(), rank, spacingKey + std::string(" in its header"));
  if (!problem.empty())
  {
    return problem;
  }
  const int bytes = elementBytes(field("ElementType"));
  if (bytes == 0)
  {
    return "has ElementType = '" + field("ElementType") +
      "' in its header, which cannot be read (MET_CHAR, MET_UCHAR, MET_SHORT, MET_USHORT, "
      "MET_INT, MET_UINT, MET_LONG, MET_ULONG, MET_LONG_LONG, MET_ULONG_LONG, MET_FLOAT, "
      "MET_DOUBLE can)";
  }
  std::vector<double> channels;
  if (!field("ElementNumberOfChannels").empty() &&
    (!numbers(field("ElementNumberOfChannels"), channels) || channels.size() != 1 ||
      !(channels[0] >= 1) || channels[0] != std::floor(channels[0])))
  {
    return "has ElementNumberOfChannels = '" + field("ElementNumberOfChannels") +
      "' in its header (a whole number >= 1 expected)";
  }
  const double bytesPerVoxel = bytes * (channels.empty() ? 1.0 : channels[0]);

  std::vector<std::string> files;
  problem = dataFiles(name, header, files);
  if (!problem.empty())
  {
    return problem;
  }
  // Every data file holds its share of the voxels (a LIST or pattern: one slab each).
  const bool compressed = isTrue(field("CompressedData"));
  const bool ascii = !field("BinaryData").empty() && !isTrue(field("BinaryData"));
  const double skip = std::atof(field("HeaderSize").c_str()); // -1: the data ends the file
  const double share = voxels / static_cast<double>(files.size());
  for (const std::string& file : files)
  {
    const std::int64_t size = mcv::fileBytes(file);
    const std::string subject = file == name ? "" : "has a data file '" + file + "' that ";
    if (size < 0)
    {
      return subject + "cannot be opened";
    }
    double offset = file == name ? static_cast<double>(header.dataOffset) : 0.0;
    std::int64_t present = size;
    if (compressed)
    {
      std::string error;
      present = mcv::inflatedBytes(file, static_cast<std::int64_t>(offset),
        mcv::Compression::ZlibOrGzip, error);
      if (present < 0)
      {
        return subject + error;
      }
      offset = 0;
    }
    else if (skip > 0)
    {
      offset = skip;
    }
    else if (skip == -1)
    {
      offset = std::max(0.0, static_cast<double>(size) - share * bytesPerVoxel);
    }
    if (!ascii)
    {
      problem = mcv::checkPresent(share, bytesPerVoxel, offset, present,
        (file == name ? std::string("the file") : "its data file '" + file + "'") +
          (compressed ? " holds, once decompressed," : " holds"));
      if (!problem.empty())
      {
        return problem;
      }
    }
  }
  return mcv::checkFitsInMemory(voxels, bytesPerVoxel);
}

//------------------------------------------------------------------------------
int vtkCheckedMetaImageReader::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Our checks first: metaio's own parsing of a bad header says less ("cannot parse file").
  this->Refused = !mcv::checkedRequestInformation(this, outputVector, this->Describe(), [&] {
    const std::string problem = this->CheckHeaderAgainstFile();
    if (!problem.empty())
    {
      return problem;
    }
    return this->Superclass::RequestInformation(request, inputVector, outputVector)
      ? std::string()
      : std::string("cannot be read");
  });
  return this->Refused ? 0 : 1;
}

//------------------------------------------------------------------------------
int vtkCheckedMetaImageReader::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return mcv::checkedSeriesRequestData(this, outputVector, this->Describe(), this->Refused,
    [&] { return this->Superclass::RequestData(request, inputVector, outputVector); });
}

//------------------------------------------------------------------------------
std::string vtkCheckedMetaImageReader::Describe()
{
  return std::string("MetaImage file '") + (this->GetFileName() ? this->GetFileName() : "") + "'";
}
