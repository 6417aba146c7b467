// The fused reduction's passes over the whole volume on the GPU: besides the
// placement (FusedPlacementCuda.h), the chain walks the volume's features three times -- the
// statistics of the normalisation (FeatureBricks::prepare), the column check of the
// normalised features and the reference sample's strata (reduceDimension). On the CPU each
// pass computes every voxel's features again; here the slab stream (SlabStream.cuh) computes
// them on the device and only a few numbers per slab (or one byte per voxel, the strata)
// come back.
//
// Same function as the CPU passes:
//  - statistics: per slab, count, sum, min, max and the squared deviations about the slab's
//    mean of every column over the rows whose channels are finite (the CPU's statsMask), and
//    the non-finite voxels per channel; combined by the caller with mergeStats as the CPU's
//    slabs are. The sums are in double in a fixed order (deterministic, not the CPU's order:
//    they agree to rounding, ~1e-16 relative);
//  - column sums: exact (per exponent integer sums, DimensionReduction.cpp's addExact),
//    extremes and non-finite values of the normalised features: bit for bit the CPU's;
//  - strata: each eligible row's centred norm of its used columns, rounded step by step as
//    the CPU rounds it, placed among the edges as std::upper_bound does: the CPU's strata.
//
// Plain C++ interface; built only with MCV_ENABLE_CUDA. Any CUDA failure returns false with
// `error` (the caller runs the CPU pass). Single-process volumes: every row is owned.
#pragma once

#include "FusedPlacementCuda.h"

#include "FeatureRows.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mcv
{
namespace cuda
{

struct FusedPassSetup
{
  ImageGrid grid;
  int channels = 0;
  FeatureSelection selection;
  int cols = 0;
  std::vector<double> offset, scale; // the normalisation (column sums, strata); empty for the statistics
  std::size_t deviceBytes = 0;       // 0: the free memory less a margin
  ResidentChannels* resident = nullptr; // optional: see FusedPlacementCuda.h
};

struct FusedPassStats
{
  int slabSlices = 0;
  std::size_t slabs = 0, bytesToDevice = 0, bytesFromDevice = 0, deviceBytes = 0, deviceUsedPeak = 0, pinnedBytes = 0;
  double setupMs = 0, fillMs = 0, waitMs = 0, totalMs = 0; // fill: host conversion; wait: for the device
};

// The statistics pass: one ColumnStats per slab (sqdev about the slab's own mean), the
// non-finite voxels per channel and the voxels with any (rows excluded from the statistics).
struct RawStatistics
{
  std::vector<mcv::detail::ColumnStats> slabs;
  std::vector<double> badPerChannel;
  double badVoxels = 0;
};
bool fusedRawStatistics(const FusedPassSetup& setup, const FusedChannelFill& fill, RawStatistics* out,
  const std::function<void(double)>& progress, FusedPassStats* stats, std::string* error);

// The column check (FeatureRows.h's DeviceColumnSums, without `attempted` and `error`):
// kExactExponents integer sums per column (column c's at bins[c * kExactExponents]),
// extremes, non-finite values and the first one (row * cols + column; +inf when none).
constexpr int kExactExponents = 256;
bool fusedColumnSums(const FusedPassSetup& setup, const FusedChannelFill& fill, DeviceColumnSums* out,
  const std::function<void(double)>& progress, FusedPassStats* stats, std::string* error);

// The strata (FeatureRows.h's DeviceStrata): stratum[row] = the number of edges <= the row's
// centred norm (float) for the rows with eligible[row] != 0 (all when eligible is null),
// notEligible for the others.
bool fusedStrata(const FusedPassSetup& setup, const FusedChannelFill& fill, const DeviceStrata& request,
  FusedPassStats* stats, std::string* error);

} // namespace cuda
} // namespace mcv
