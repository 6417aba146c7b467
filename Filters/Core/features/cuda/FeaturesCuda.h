// GPU path of the multichannel feature vectors (Filters/Core/features/FeatureVectors.h). Plain C++
// interface (no CUDA types), so the core can call it; built only when MCV_ENABLE_CUDA is on
// (the core then defines MCV_HAS_CUDA). Every method returns false with `error` set on any
// CUDA failure (allocation included), so the core can fall back to the CPU.
//
// The n x F matrix lives on the device while it is filled channel by channel (one float
// channel uploaded at a time), normalised there, and downloaded once into the caller's
// buffer. Same per-voxel float arithmetic as the CPU path; statistics in double.
#pragma once

#include "FeatureVectors.h"
#include "NonCopyable.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace mcv
{
namespace cuda
{

class FeatureMatrixGpu : NonCopyable
{
public:
  FeatureMatrixGpu();
  ~FeatureMatrixGpu();

  // Device buffers for a rows x cols matrix and one channel of `rows` floats.
  bool allocate(std::size_t rows, int cols, std::string* error);

  // Raw features of one channel (host floats, non-finite values allowed) into columns
  // [firstColumn, firstColumn + selection.perChannel()).
  bool addChannel(const float* hostValues, bool hasNonFinite, const ImageGrid& grid,
    const FeatureSelection& selection, int firstColumn, std::string* error);

  // Uploads the row mask (n bytes, 1 = row left out and zeroed); null: every row valid.
  bool setMask(const unsigned char* hostMask, std::string* error);

  // Same contract as detail::columnStatsCPU.
  bool columnStats(bool deviation, mcv::detail::ColumnStats& stats, std::string* error);

  // Same contract as detail::applyNormalizationCPU.
  bool applyNormalization(
    const std::vector<double>& offset, const std::vector<double>& scale, std::string* error);

  // The whole matrix into host memory (rows x cols floats).
  bool download(float* hostOut, std::string* error);

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace cuda
} // namespace mcv
