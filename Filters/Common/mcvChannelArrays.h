// VTK point arrays -> the core's channels (ChannelView), shared by the suite's VTK filters
// (vtkBestViewpoint, vtkMultichannelFeatures). Header-only: each filter module includes it
// by relative path and links nothing more than VTK::CommonCore.
//
// Every component of every array is one channel. Arrays of a type the core reads directly
// (8/16/32-bit integers, float, double) in VTK's standard (AOS) layout are used in place;
// anything else (64-bit integers, SOA arrays...) goes through one contiguous double copy.
#pragma once

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"

#include "OpacityFunction.h" // mcv::ChannelView, mcv::ScalarType (Filters/Core)

#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace mcv
{
namespace vtkhelpers
{

inline bool toScalarType(int vtkType, mcv::ScalarType& type)
{
  switch (vtkType)
  {
    case VTK_CHAR:
#if VTK_TYPE_CHAR_IS_SIGNED
      type = mcv::ScalarType::Int8;
#else
      type = mcv::ScalarType::UInt8;
#endif
      return true;
    case VTK_SIGNED_CHAR:
      type = mcv::ScalarType::Int8;
      return true;
    case VTK_UNSIGNED_CHAR:
      type = mcv::ScalarType::UInt8;
      return true;
    case VTK_SHORT:
      type = mcv::ScalarType::Int16;
      return true;
    case VTK_UNSIGNED_SHORT:
      type = mcv::ScalarType::UInt16;
      return true;
    case VTK_INT:
      type = mcv::ScalarType::Int32;
      return true;
    case VTK_UNSIGNED_INT:
      type = mcv::ScalarType::UInt32;
      return true;
    case VTK_FLOAT:
      type = mcv::ScalarType::Float32;
      return true;
    case VTK_DOUBLE:
      type = mcv::ScalarType::Float64;
      return true;
    default:
      return false;
  }
}

// "'a', 'b'" or "none": the point arrays of `pd`, for error messages.
inline std::string availableArrays(vtkPointData* pd)
{
  std::ostringstream os;
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    const char* name = pd->GetArrayName(i);
    os << (i ? ", " : "") << "'" << (name ? name : "(unnamed)") << "'";
  }
  return pd->GetNumberOfArrays() ? os.str() : std::string("none");
}

struct ChannelArrays
{
  std::vector<vtkSmartPointer<vtkDataArray>> converted; // keeps double copies alive
  std::vector<mcv::ChannelView> views;
  std::vector<std::string> labels; // "'name'" or "'name' component c" (for messages)
  std::vector<std::string> names;  // "name" or "name_<component name or c>" (for columns)
};

// Channels of `arrays` (each of `count` tuples). Returns "" or what is wrong.
inline std::string toChannels(
  const std::vector<vtkDataArray*>& arrays, std::size_t count, ChannelArrays& out)
{
  out = ChannelArrays();
  for (vtkDataArray* dataArray : arrays)
  {
    const char* name = dataArray->GetName() ? dataArray->GetName() : "(unnamed)";
    if (static_cast<std::size_t>(dataArray->GetNumberOfTuples()) != count)
    {
      std::ostringstream os;
      os << "Point array '" << name << "' has " << dataArray->GetNumberOfTuples() << " tuples for "
         << count << " voxels.";
      return os.str();
    }
    if (dataArray->GetNumberOfComponents() < 1)
    {
      return std::string("Point array '") + name + "' has no components.";
    }
    mcv::ScalarType type;
    vtkDataArray* use = dataArray;
    if (!toScalarType(dataArray->GetDataType(), type) || !dataArray->HasStandardMemoryLayout())
    {
      // 64-bit integers, bit arrays, SOA layouts...: a contiguous double copy.
      vtkNew<vtkDoubleArray> copy;
      copy->DeepCopy(dataArray);
      out.converted.emplace_back(copy.Get());
      use = copy;
      type = mcv::ScalarType::Float64;
    }
    const int components = use->GetNumberOfComponents();
    for (int c = 0; c < components; ++c)
    {
      mcv::ChannelView view;
      view.data = use->GetVoidPointer(0);
      view.type = type;
      view.numComponents = components;
      view.component = c;
      out.views.push_back(view);
      std::ostringstream label;
      label << "'" << name << "'";
      std::string columnName = name;
      if (components > 1)
      {
        label << " component " << c;
        const char* componentName = dataArray->GetComponentName(c);
        columnName += "_" +
          (componentName && *componentName ? std::string(componentName) : std::to_string(c));
      }
      out.labels.push_back(label.str());
      out.names.push_back(columnName);
    }
  }
  return std::string();
}

} // namespace vtkhelpers
} // namespace mcv
