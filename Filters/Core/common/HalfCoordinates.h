// Reduced coordinates stored as float16: VTK 9.2 has no half-float array, so
// the suite's convention is a uint16 array holding IEEE binary16 bits (an unsigned-short
// ReducedCoordinates array is read as float16). These are the only conversions the suite
// uses, through Eigen::half (round to nearest even; F16C where the compiler targets it).
//
// binary16 has an 11-bit significand: a value is kept to within 2^-11 of itself (relative),
// down to 2^-14 ~ 6.1e-5 (below, subnormals keep an absolute 2^-25). Its largest finite
// value is 65504; larger magnitudes become +-inf.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace mcv
{

// The largest finite binary16 value.
constexpr float kHalfMax = 65504.0f;

// Rounds n floats to binary16 bits. Returns how many finite inputs overflowed (|x| > 65504
// after rounding: stored as +-inf), so a caller can refuse coordinates float16 cannot hold.
inline std::size_t floatsToHalves(const float* in, std::size_t n, std::uint16_t* out)
{
  std::size_t overflow = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const Eigen::half h(in[i]);
    out[i] = Eigen::numext::bit_cast<std::uint16_t>(h);
    overflow += (std::isfinite(in[i]) && !(Eigen::numext::isfinite)(h)) ? 1 : 0;
  }
  return overflow;
}

// Widens n binary16 values to float (exact: every half is a float).
inline void halvesToFloats(const std::uint16_t* in, std::size_t n, float* out)
{
  for (std::size_t i = 0; i < n; ++i)
  {
    out[i] = static_cast<float>(Eigen::numext::bit_cast<Eigen::half>(in[i]));
  }
}

// Readers decode this many voxels at a time into a float scratch (never a float copy of
// the whole array): 3 x 64 Ki floats = 768 KiB.
constexpr std::size_t kHalfChunkVoxels = std::size_t(1) << 16;
// The reduction places this many rows at a time into a float scratch when it writes
// float16 coordinates (DimensionReduction.h): 12 MiB in 3D, amortising each call's setup.
constexpr std::size_t kHalfPlacementRows = std::size_t(1) << 20;

} // namespace mcv
