// GPU path of the out-of-sample placement (Filters/Core/reduction/OutOfSample.h). Plain C++ interface
// (no CUDA types) so the core can call it; built only when MCV_ENABLE_CUDA is on. Returns
// false with `error` set on any CUDA failure (allocation included): the core then runs the
// CPU path.
//
// The rows are uploaded once, the coordinates downloaded once. Per row, a tiled kernel
// (references through shared memory, one query per thread, its 8 best float distances in
// registers ordered by (distance, index)) gives candidates; a second kernel applies the
// canonical rule of ExactKnn.h (double distances rounded like the CPU's, ties by index),
// checks it with the float error bound and computes the barycentric weights and the
// coordinates; rows whose check fails get an exact double scan of every reference. So the
// GPU picks the same neighbours as the CPU. With pruneTiles the references are ordered
// into compact tiles at upload, the rows of a chunk are sorted by their two nearest tiles, and a
// warp skips a tile whose bounding box shows it cannot improve any of its rows' candidates:
// the same candidates, fewer references scanned.
#pragma once

#include "NonCopyable.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace mcv
{
namespace cuda
{

constexpr int kMaxPlacementDimension = 64; // D (features used)
constexpr int kMaxPlacementNeighbors = 6;  // k (8 float candidates are kept per row)

struct PlacementInput
{
  const float* refX = nullptr; // M x D reference features, row-major
  const float* refY = nullptr; // M x d their embedding
  std::size_t M = 0;
  int D = 0;
  int d = 0;
  const float* rows = nullptr; // n x dim, row-major
  std::size_t n = 0;
  int dim = 0;
  const int* columns = nullptr; // D column indices into a row, or null (dim == D)
  int neighbors = 3;
  double regularization = 1e-3;
  double distanceMargin = 0; // floatDistanceMargin(D) of ExactKnn.h
  // Skip whole tiles of references that cannot hold a candidate (a bounding-box lower bound
  // on compact tiles, see OutOfSampleCuda.cu); the same candidates either way. Only with at
  // least 32 tiles of 32 references. false: every reference is scanned for every row (the
  // benchmarks' in-run baseline).
  bool pruneTiles = true;
  // With pruneTiles: a warp checks the box of its rows against 32 tiles at once before the
  // per-row checks (OutOfSampleCuda.cu); the same candidates. false: every row checks every
  // tile (the benchmark's in-run baseline).
  bool warpBoxFilter = true;
  // With pruneTiles: the exact float distance only for references that a bound from the dot
  // product q.r does not rule out (OutOfSampleCuda.cu); the same candidates. false: the
  // exact distance to every reference of a scanned tile (the benchmark's in-run baseline).
  bool dotProductFilter = true;
};

struct PlacementStats
{
  double uploadMs = 0, computeMs = 0, downloadMs = 0;
  std::size_t radiusScans = 0; // rows solved by the exact scan
  int tiles = 0;               // reference tiles (of 32, the pruning's)
  double tilesPerRow = 0;      // tiles scanned per row placed (tiles when not pruning)
};

// out: n x d floats; neighbors (optional): n x k references each row was placed by.
// progress (optional) receives the fraction of rows done, from the calling thread.
bool placeOutOfSample(const PlacementInput& input, float* out, std::uint32_t* neighbors,
  const std::function<void(double)>& progress, PlacementStats* stats, std::string* error);

// The same placement with the references resident on the device and rows that are already
// there: the fused path (FusedPlacementCuda.h) computes a slab's features on the device and
// places them without a round trip. Same kernels, same answers as placeOutOfSample. The
// column list lives in this file's constant memory: one PlacementOnDevice at a time.
class PlacementOnDevice : NonCopyable
{
public:
  PlacementOnDevice();
  ~PlacementOnDevice();

  // The references and settings of `input` (its rows and n are not used; dim and columns
  // describe the rows place() will get). `slots`: sets of scratch buffers, one per stream
  // placing at the same time, each for up to maxRows rows at once (larger calls go in
  // steps). Replaces an earlier upload.
  bool upload(const PlacementInput& input, int slots, std::size_t maxRows, std::string* error);
  // Queues the placement of n rows (device memory, n x dim) into deviceOut (n x d) and
  // deviceNeighbors (n x k, optional) on `stream` (a cudaStream_t; null: the default
  // stream) with the scratch of `slot`. Nothing waits; errors of the kernels show at the
  // stream's next synchronisation. mergeEqualRows: a run of consecutive rows with equal
  // features is placed once (as the CPU path does; the same coordinates, bit for bit).
  // deviceDistance (optional, n floats): each row's distance to its nearest reference over
  // `radius` (ModelDistance.h), as the CPU computes it.
  bool place(const float* deviceRows, std::size_t n, float* deviceOut, unsigned* deviceNeighbors, int slot,
    void* stream, bool mergeEqualRows, std::string* error, float* deviceDistance = nullptr, double radius = 0.0);
  // Rows solved by the exact scan since upload (waits for the device).
  bool radiusScans(std::size_t* count, std::string* error);
  // Reference tiles, and tiles scanned per row placed since upload (waits for the device).
  bool tileVisits(int* tiles, double* perRow, std::string* error);
  // Device bytes held: upload's, and what it needs for M references and per slot.
  std::size_t deviceBytes() const;
  static std::size_t referenceBytes(std::size_t M, int D, int d);
  static std::size_t scratchBytesPerSlot(std::size_t maxRows);
  void release();

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace cuda
} // namespace mcv
