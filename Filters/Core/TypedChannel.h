// Typed access to a ChannelView: calls visit(const T* data) with the channel's own scalar
// type, so per-voxel loops are compiled once per type. Shared by OpacityFunction.cpp and
// FeatureVectors.cpp.
#pragma once

#include "OpacityFunction.h"

#include <cstdint>

namespace mcv
{

template <typename Visit>
void withTypedData(const ChannelView& c, Visit&& visit)
{
  switch (c.type)
  {
    case ScalarType::Int8:
      visit(static_cast<const std::int8_t*>(c.data));
      break;
    case ScalarType::UInt8:
      visit(static_cast<const std::uint8_t*>(c.data));
      break;
    case ScalarType::Int16:
      visit(static_cast<const std::int16_t*>(c.data));
      break;
    case ScalarType::UInt16:
      visit(static_cast<const std::uint16_t*>(c.data));
      break;
    case ScalarType::Int32:
      visit(static_cast<const std::int32_t*>(c.data));
      break;
    case ScalarType::UInt32:
      visit(static_cast<const std::uint32_t*>(c.data));
      break;
    case ScalarType::Float32:
      visit(static_cast<const float*>(c.data));
      break;
    case ScalarType::Float64:
      visit(static_cast<const double*>(c.data));
      break;
  }
}

} // namespace mcv
