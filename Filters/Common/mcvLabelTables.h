// Label tables of atlas channels: the names of the integer values of a label volume (AAL's
// 1 = "Precentral_L"), carried with the volume so that a probe says the name.
//
// Where they come from: the text file beside the volume that MRIcron's atlases ship with
// (Debian's mricron-data: aal.nii.gz has aal.nii.txt, one line per label,
// "<value> <name> [<more columns>]"). A reader of the suite that finds such a file beside
// the file it reads (<file without .gz>.txt, else <stem>.txt) attaches the table.
//
// How they travel: a field-data vtkStringArray named `<channel>_labels` (the channel's
// point array name + "_labels"), one entry per label, "<value>\t<name>". Filters that pass
// their input's field data (MultichannelFeatures, DimensionReduction) keep it; MergeChannels
// renames it with its channel; ExtractVoxels (the probe's read-back) passes the tables on,
// so the probe reads the voxel and the names in one fetch. A colour-only .lut (Brodmann's)
// has no names and gives no table.
//
// Header-only; the table is built and read by hand because it is a few dozen lines of a
// plain text format that no library of ParaView reads.
#pragma once

#include "vtkFieldData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "mcvFileNames.h"

namespace mcv
{
namespace vtkhelpers
{

inline const char* labelTableSuffix()
{
  return "_labels";
}

inline std::string labelTableName(const std::string& channel)
{
  return channel + labelTableSuffix();
}

// True for a field array name of the label table form.
inline bool isLabelTableName(const char* name)
{
  const std::size_t n = std::strlen(labelTableSuffix());
  const std::size_t len = name ? std::strlen(name) : 0;
  return len > n && std::strcmp(name + len - n, labelTableSuffix()) == 0;
}

// The label file beside `volumePath` ("" when there is none): <path without .gz>.txt
// (MRIcron: aal.nii.gz -> aal.nii.txt), else <folder>/<stem>.txt (aal.txt).
inline std::string labelFileBeside(const std::string& volumePath)
{
  std::string base = volumePath;
  if (base.size() > 3 && base.compare(base.size() - 3, 3, ".gz") == 0)
  {
    base.resize(base.size() - 3);
  }
  const std::size_t slash = volumePath.find_last_of("/\\");
  const std::string folder = slash == std::string::npos ? "" : volumePath.substr(0, slash + 1);
  for (const std::string& candidate : { base + ".txt", folder + fileStem(volumePath) + ".txt" })
  {
    if (candidate != volumePath && std::ifstream(candidate).good())
    {
      return candidate;
    }
  }
  return std::string();
}

// Reads a label file: each non-empty line that does not start with '#' is "<integer value>
// <name> ...". Returns the table (named labelTableName(channel)), or null with `error` set
// (naming the file and the line) when a line does not start with an integer and a name.
inline vtkSmartPointer<vtkStringArray> readLabelFile(
  const std::string& path, const std::string& channel, std::string& error)
{
  std::ifstream in(path);
  if (!in)
  {
    error = "cannot open the label file '" + path + "'";
    return nullptr;
  }
  auto table = vtkSmartPointer<vtkStringArray>::New();
  table->SetName(labelTableName(channel).c_str());
  std::string line;
  for (int number = 1; std::getline(in, line); ++number)
  {
    std::istringstream fields(line);
    std::string value, name;
    if (!(fields >> value) || value[0] == '#')
    {
      continue;
    }
    char* end = nullptr;
    const long v = std::strtol(value.c_str(), &end, 10);
    if (!end || *end != '\0' || !(fields >> name))
    {
      error = "the label file '" + path + "' line " + std::to_string(number) +
        " is not '<integer value> <name>': '" + line + "'";
      return nullptr;
    }
    table->InsertNextValue(std::to_string(v) + "\t" + name);
  }
  return table;
}

} // namespace vtkhelpers
} // namespace mcv
