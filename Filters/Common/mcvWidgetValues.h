// The flat Gaussian-widget list (8 values per widget: cx, cy, cz, sigma, r, g, b,
// opacity) behind the `GaussianWidgets` property of the representation, BestViewpoint and
// ReducedDomain. ParaView sets a variable-length double property element by element
// (set_number_command + use_index): the representation and vtkGaussianWidgetsAlgorithm (the
// two filters' base) forward their Set/Get methods here.
// Header-only, like mcvChannelArrays.h.
#pragma once

#include <cstddef>
#include <vector>

namespace mcv
{
namespace vtkhelpers
{

class WidgetValues
{
public:
  // Each setter returns true when the list changed (the caller then calls Modified()).
  bool SetNumber(int count)
  {
    const std::size_t n = static_cast<std::size_t>(count < 0 ? 0 : count);
    if (n == this->Values.size())
    {
      return false;
    }
    this->Values.resize(n, 0.0);
    return true;
  }

  bool Set(int index, double value)
  {
    if (index < 0)
    {
      return false;
    }
    const std::size_t i = static_cast<std::size_t>(index);
    if (i >= this->Values.size())
    {
      this->Values.resize(i + 1, 0.0);
    }
    else if (this->Values[i] == value)
    {
      return false;
    }
    this->Values[i] = value;
    return true;
  }

  int GetNumber() const { return static_cast<int>(this->Values.size()); }

  double Get(int index) const
  {
    return index >= 0 && static_cast<std::size_t>(index) < this->Values.size()
      ? this->Values[static_cast<std::size_t>(index)]
      : 0.0;
  }

  const double* Data() const { return this->Values.data(); }
  std::size_t Size() const { return this->Values.size(); }

private:
  std::vector<double> Values;
};

} // namespace vtkhelpers
} // namespace mcv
