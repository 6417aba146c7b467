// A channel of a VTK-free interleaved array: its scalar type and where its values are.
// Shared by the features (FeatureVectors) and the best viewpoint (OpacityFunction).
#pragma once

namespace mcv
{

enum class ScalarType
{
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Float32,
  Float64
};

// One channel of an interleaved array: value of voxel v is data[v * numComponents + component].
struct ChannelView
{
  const void* data = nullptr;
  ScalarType type = ScalarType::Float32;
  int numComponents = 1;
  int component = 0;
};

} // namespace mcv
