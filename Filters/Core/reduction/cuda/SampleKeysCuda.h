// The reference sample's key scans on the GPU (Filters/Core/reduction/ReferenceSample.cpp):
// the sampler draws voxels by a random key per voxel (sampleKey: a bijection of the voxel's
// global index), and finds the voxels below a key limit by hashing every voxel -- a giga-
// voxel volume's billion keys take the CPU half a second per scan, the GPU milliseconds.
//
// Plain C++ interface; built only with MCV_ENABLE_CUDA. False with `error` on a CUDA failure
// (the caller scans on the CPU).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mcv
{
namespace cuda
{

// The rows r of [0, n) with sampleKey(seed, firstGlobal + r) <= limit, ascending.
bool rowsWithKeyAtMost(std::uint64_t seed, std::int64_t firstGlobal, std::size_t n, std::uint64_t limit,
  std::vector<std::size_t>* rows, std::string* error);

} // namespace cuda
} // namespace mcv
