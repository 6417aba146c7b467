// VTK point arrays -> the core's channels (ChannelView), shared by the suite's VTK filters
// (vtkBestViewpoint, vtkMultichannelFeatures). Header-only: each filter module includes it
// by relative path and links nothing more than VTK::CommonCore.
//
// Every component of every array is one channel. Arrays of a type the core reads directly
// (8/16/32-bit integers, float, double) in VTK's standard (AOS) layout are used in place;
// anything else (64-bit integers, SOA arrays...) goes through one contiguous double copy.
#pragma once

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"

#include "OpacityFunction.h" // mcv::ChannelView, mcv::ScalarType (Filters/Core)
#include "mcvInternalArrays.h" // isInternalArray

#include <algorithm>
#include <cstddef>
#include <functional>
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

// The `Channels` property of a filter: point-array names, in order. Add and Clear return
// whether the list changed, so the filter calls Modified() only then.
class ChannelSelection
{
public:
  bool Add(const char* name)
  {
    if (!name || !*name)
    {
      return false;
    }
    this->Names.emplace_back(name);
    return true;
  }
  bool Clear()
  {
    const bool changed = !this->Names.empty();
    this->Names.clear();
    return changed;
  }
  int Size() const { return static_cast<int>(this->Names.size()); }
  const char* Get(int index) const
  {
    return index < 0 || index >= this->Size() ? nullptr : this->Names[index].c_str();
  }
  const std::vector<std::string>& GetNames() const { return this->Names; }

private:
  std::vector<std::string> Names;
};

// The arrays a filter works on: the named point arrays (each must exist and be numeric;
// duplicates once), or, when no name is given, what `defaults` picks. Returns "" or the
// error message; `filterLabel` names the filter in it.
inline std::string selectChannelArrays(vtkDataSet* input, const std::vector<std::string>& names,
  const std::function<std::vector<vtkDataArray*>(vtkPointData*)>& defaults,
  const char* filterLabel, std::vector<vtkDataArray*>& arrays)
{
  arrays.clear();
  vtkPointData* pd = input->GetPointData();
  bool namedChannel = false;
  for (const std::string& name : names)
  {
    if (isInternalArray(name.c_str()))
    {
      // ParaView's own marks, never a channel: in a split run the GUI's array list offers
      // vtkGhostType (a parallel source adds it) where a serial run has none, so the same
      // settings would otherwise read a different set of channels, or miss the array on a
      // process whose block was assembled from the others' pieces (mcvGatherBlock.h).
      continue;
    }
    namedChannel = true;
    vtkAbstractArray* abstractArray = pd->GetAbstractArray(name.c_str());
    if (!abstractArray)
    {
      return "No point array named '" + name + "' in the input (point arrays: " +
        availableArrays(pd) + ").";
    }
    vtkDataArray* dataArray = vtkDataArray::SafeDownCast(abstractArray);
    if (!dataArray)
    {
      return "Point array '" + name + "' is not numeric (" + abstractArray->GetClassName() + ").";
    }
    if (std::find(arrays.begin(), arrays.end(), dataArray) == arrays.end())
    {
      arrays.push_back(dataArray);
    }
  }
  if (!namedChannel)
  {
    arrays = defaults(pd);
  }
  if (arrays.empty())
  {
    const bool cellArrays = input->GetCellData()->GetNumberOfArrays() > 0;
    return std::string("Input has no point scalar array: ") + filterLabel +
      " needs at least one numeric point-data array (point arrays: " + availableArrays(pd) +
      ")" +
      (cellArrays ? "; it has cell arrays: convert them with Cell Data to Point Data." : ".");
  }
  return std::string();
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

// The warning of a filter that computes feature vectors from the channels when there is
// only one: "" for several channels. One channel gives a feature space of that channel's
// intensity and its neighbourhood alone; the suite is made to separate what several
// channels tell apart, so the warning says how to get them into one volume.
inline std::string oneChannelWarning(const ChannelArrays& channels, int features)
{
  if (channels.views.size() != 1)
  {
    return std::string();
  }
  std::ostringstream os;
  os << "Only one channel (" << channels.labels[0] << "): its " << features
     << " features describe one intensity and its neighbourhood, so the reduced domain "
        "separates no more than that channel's values and edges do. To explore several "
        "channels, put them into one volume: merge the files of the channels with Merge "
        "Channels (Filters > Multichannel > Merge Channels; in Python MergeChannels(Input=[a, "
        "b, c])), or open a multichannel file (a 4D NIfTI with TimeAsVector on, or an array "
        "with one component per channel), and select the channels in Channels.";
  return os.str();
}

} // namespace vtkhelpers
} // namespace mcv
