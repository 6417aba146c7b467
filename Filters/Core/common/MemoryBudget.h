// Memory check before a large allocation: a volume too large for this process gets a
// clear message saying how much is needed and how much there is, instead of a crash or a
// std::bad_alloc half-way. Each MPI rank checks its own piece.
//
// The estimates count the host memory a filter allocates beyond its input (which is already
// in memory); the VTK filters call check*Memory before computing and report the message as
// their error.
#pragma once

#include <cstddef>
#include <string>

namespace mcv
{

// Bytes this process can still allocate: MCV_MEMORY_LIMIT_MB (MiB, for tests) when set to
// a number >= 0; else MemAvailable of /proc/meminfo (fallback: sysconf's available pages),
// lowered to what the process's cgroup limit leaves (batch systems such as Slurm enforce
// theirs that way) and to what its address-space limit (ulimit -v) leaves above its
// current virtual size. SIZE_MAX when nothing says.
std::size_t availableMemoryBytes();

// "2.7 GiB", "512.0 MiB", "12.0 KiB", "100 B" (one decimal, rounded up or down).
std::string formatBytes(std::size_t bytes, bool roundUp = false);
// "7.1 M", "12.3 k", "950".
std::string formatCount(std::size_t count);

// Estimated bytes (saturating at SIZE_MAX):
// MultichannelFeatures: the voxels x features float output, one channel's float working
// copy and the non-finite mask (one byte per voxel).
std::size_t featureBytes(std::size_t voxels, int features);
// DimensionReduction's coordinates: rows x dimensions floats, or with halfCoordinates
// (CoordinatePrecision Float16) 2 bytes each (6 per voxel in 3D) plus the float scratch
// of one chunk of rows (kHalfPlacementRows of HalfCoordinates.h).
std::size_t coordinateBytes(std::size_t rows, int dimensions, bool halfCoordinates);
// DimensionReduction: the coordinates, plus a float copy of the rows x features input when
// it is not float already.
std::size_t reductionBytes(std::size_t rows, int features, int dimensions, bool inputIsFloat,
  bool halfCoordinates = false);
// DimensionReduction on the channels (the fused path): the coordinates, one byte per row for
// the Foreground mask and one for the sample's strata, and the working memory of one slab
// of features (FeatureBricks::workingBytes); no rows x features array.
std::size_t fusedReductionBytes(std::size_t rows, int dimensions, std::size_t slabBytes,
  bool halfCoordinates = false);
// BestViewpoint: the opacity and the Harris response, one float each per voxel.
std::size_t viewpointBytes(std::size_t voxels);

// "" when bytesNeeded fits in availableMemoryBytes(); else one line:
// "<what> needs 2.7 GiB[ for <forWhat>] but only 1.2 GiB is available on this process;
// <advice>crop or subsample the volume, or run on more MPI ranks (mpiexec -np R pvbatch
// --mpi) so that each holds a smaller piece." `advice` (may be empty) ends with ", ".
std::string checkMemory(std::size_t bytesNeeded, const char* what);
std::string checkMemory(std::size_t bytesNeeded, const char* what, const std::string& forWhat,
  const std::string& advice);

// The checks of the filters (their estimate, their wording).
std::string checkFeatureMemory(std::size_t voxels, int features);
std::string checkReductionMemory(std::size_t rows, int features, int dimensions, bool inputIsFloat,
  bool halfCoordinates = false);
std::string checkFusedReductionMemory(std::size_t rows, int features, int dimensions, std::size_t slabBytes,
  bool halfCoordinates = false);
std::string checkViewpointMemory(std::size_t voxels);

} // namespace mcv
