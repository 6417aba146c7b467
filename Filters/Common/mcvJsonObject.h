// One JSON object from text, as the suite's file readers take it (OME-Zarr .zattrs and
// .zarray, the reduction model's header): VTK's jsoncpp, and the first line of its message
// for the error that names the file. Header-only, like mcvChannelArrays.h.
#pragma once

#include "vtk_jsoncpp.h"

#include <sstream>
#include <string>

namespace mcv
{
namespace vtkhelpers
{

// True when `text` is one JSON object, then in `root`; else false with the first line of
// the parser's message in `why` (empty when the text is valid JSON but no object).
inline bool parseJsonObject(const std::string& text, Json::Value& root, std::string& why)
{
  Json::CharReaderBuilder builder;
  std::string errors;
  std::istringstream in(text);
  if (!Json::parseFromStream(builder, in, &root, &errors) || !root.isObject())
  {
    why = errors.substr(0, errors.find('\n'));
    return false;
  }
  return true;
}

} // namespace vtkhelpers
} // namespace mcv
