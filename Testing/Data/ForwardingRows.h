// A FeatureRows that hands every call on to another one: a test or benchmark derives from it
// to watch one call (the gathers counted or timed) and leaves the others as they are.
#pragma once

#include "FeatureRows.h"

namespace mcv
{
namespace testing
{

class ForwardingRows : public FeatureRows
{
public:
  explicit ForwardingRows(FeatureRows& rows)
    : rows_(rows)
  {
  }
  std::size_t rows() const override { return rows_.rows(); }
  int cols() const override { return rows_.cols(); }
  std::size_t blockCount() const override { return rows_.blockCount(); }
  std::size_t blockBegin(std::size_t b) const override { return rows_.blockBegin(b); }
  const float* block(std::size_t b) override { return rows_.block(b); }
  void gather(const std::size_t* index, std::size_t n, float* out) override { rows_.gather(index, n, out); }
  DevicePlacementReport placeOnDevice(const DevicePlacement& request) override { return rows_.placeOnDevice(request); }
  DeviceColumnSums columnSumsOnDevice(const std::function<void(double)>& progress) override
  {
    return rows_.columnSumsOnDevice(progress);
  }
  DevicePassReport strataOnDevice(const DeviceStrata& request) override { return rows_.strataOnDevice(request); }

private:
  FeatureRows& rows_;
};

} // namespace testing
} // namespace mcv
