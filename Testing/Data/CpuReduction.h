// Reduction options of the core tests: one method on the CPU, with the graph methods'
// neighbourhood size, landmark count and reference sample size given (PCA ignores them).
// Header-only.
#pragma once

#include "DimensionReduction.h"

#include <cstddef>

namespace mcv
{
namespace testing
{

inline ReductionOptions cpuReduction(ReductionMethod method, int outputDimension, int neighbors,
  int landmarks, std::size_t referenceSampleSize)
{
  ReductionOptions o;
  o.method = method;
  o.outputDimension = outputDimension;
  o.device = Device::CPU;
  o.numberOfNeighbors = neighbors;
  o.numberOfLandmarks = landmarks;
  o.referenceSampleSize = referenceSampleSize;
  return o;
}

} // namespace testing
} // namespace mcv
