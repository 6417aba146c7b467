#include "ReductionModel.h"

#include "DimensionReduction.h"
#include "ReductionMethods.h"

#include <cmath>

namespace mcv
{

namespace
{
template <class T>
bool allFinite(const std::vector<T>& values)
{
  for (const T& v : values)
  {
    if (!std::isfinite(v))
    {
      return false;
    }
  }
  return true;
}
} // namespace

const char* reductionMethodName(ReductionMethod method)
{
  const ReductionMethodInfo* info = findReductionMethod(method);
  return info ? info->name : "unknown";
}

bool reductionMethodFromName(const std::string& name, ReductionMethod& method)
{
  const ReductionMethodInfo* info = findReductionMethod(name);
  if (info)
  {
    method = info->method;
  }
  return info != nullptr;
}

std::string ReductionModel::check() const
{
  if (!findReductionMethod(method))
  {
    return "unknown reduction method " + std::to_string(static_cast<int>(method));
  }
  if (outputDimension != 2 && outputDimension != 3)
  {
    return "output dimension " + std::to_string(outputDimension) + " (2 or 3 expected)";
  }
  if (featureColumns < 2)
  {
    return std::to_string(featureColumns) + " feature columns (at least 2 expected)";
  }
  const int D = usedCount();
  if (D < 2)
  {
    return std::to_string(D) + " used feature columns (at least 2 expected)";
  }
  for (std::size_t i = 0; i < usedColumns.size(); ++i)
  {
    if (usedColumns[i] < 0 || usedColumns[i] >= featureColumns || (i > 0 && usedColumns[i] <= usedColumns[i - 1]))
    {
      return "used column " + std::to_string(usedColumns[i]) + " is not an increasing index below " +
        std::to_string(featureColumns);
    }
  }
  if (references < static_cast<std::size_t>(outputDimension) + 2)
  {
    return std::to_string(references) + " reference points (at least " + std::to_string(outputDimension + 2) +
      " expected)";
  }
  if (referenceFeatures.size() != references * static_cast<std::size_t>(D))
  {
    return "reference features hold " + std::to_string(referenceFeatures.size()) + " values, not " +
      std::to_string(references) + " x " + std::to_string(D);
  }
  if (referenceCoordinates.size() != references * static_cast<std::size_t>(outputDimension))
  {
    return "reference coordinates hold " + std::to_string(referenceCoordinates.size()) + " values, not " +
      std::to_string(references) + " x " + std::to_string(outputDimension);
  }
  if (findReductionMethod(method)->projects &&
    (pcaMean.size() != static_cast<std::size_t>(D) ||
      pcaAxes.size() != static_cast<std::size_t>(D) * static_cast<std::size_t>(outputDimension)))
  {
    return "the PCA basis is not " + std::to_string(D) + " x " + std::to_string(outputDimension);
  }
  if (!allFinite(referenceFeatures) || !allFinite(referenceCoordinates) || !allFinite(pcaMean) ||
    !allFinite(pcaAxes))
  {
    return "it holds non-finite values (NaN or Inf)";
  }
  if (!std::isfinite(referenceRadius) || referenceRadius < 0)
  {
    return "its reference radius is not a finite, non-negative number";
  }
  return {};
}

} // namespace mcv
