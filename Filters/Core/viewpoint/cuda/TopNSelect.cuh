// Top-N selection on the device: the N largest positive finite scores of a device score
// volume, ordered by score descending then linear index ascending (the CPU contract of
// selectTopResponsesCPU). Only the N indices and scores come back to the host.
//
// Radix select on the float bits (positive floats order like their bit patterns):
//   level 1: histogram of the top 11 bits over the volume (fused into the Harris kernel, or
//            histogramLevel1) -> the bin b1 that holds the N-th largest score;
//   compaction: a stable cub::DeviceSelect of the candidates with bits >= b1 << 21 (a few
//            times N voxels: everything above the N-th score's bin, and that bin), in index
//            order -> the list;
//   levels 2 and 3 (11 and 10 bits) on the list -> the exact threshold T and `need`, the
//            number of ties == T that still fit;
//   the list entries > T and the first `need` ties == T (index order) -> <= N survivors;
//            a stable radix sort of them by score descending.
// Fast path (N <= 2048; no host synchronisation until the N results come back): the
// compaction is a bandwidth-bound kernel (float4 loads, one atomic per warp holding a
// candidate) into a list of at most kFastListCapacity entries, in no particular order
// (given the row maxima of the Harris kernel, it reads those and only the segments of two
// rows of 32 whose maximum reaches the level-1 bin: a few times N of the volume's rows);
// one block then runs levels 2 and 3 and gathers the survivors (if more ties == T exist
// than places, it bitonic-sorts the ties by index); N / 16 blocks then put each survivor at
// its rank by (score desc, index asc), counted against all the others.
// Slow path (larger N, a list longer than the capacity, or more than 2048 ties at T): the
// host reads the list size after level 1, and stable CUB selects in index order and a
// stable CUB radix sort do the same steps.
#pragma once

#include "TopResponses.h"
#include "NonCopyable.h"

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace mcv
{
namespace cuda
{
namespace detail
{

// The largest N of the fast path (one block gathers the survivors).
constexpr int kTopNFastMaxN = 2048;

struct SelectState
{
  unsigned long long total = 0;    // candidates (R > 0, finite)
  unsigned long long above = 0;    // candidates strictly above the current bin / threshold
  unsigned long long need = 0;     // ties == threshold taken (level 3)
  unsigned long long listSize = 0; // candidates in or above the level-1 bin
  unsigned int prefix = 0;         // bin bits fixed so far
  unsigned int threshold = 0;      // T (bit pattern)
  unsigned int low = 0;            // compaction bound: bits >= low (0xFFFFFFFF: none)
  int takeAll = 0;                 // total <= N: every candidate is taken
  int overflow = 0;                // fast path: 1 = list too long (slow path), 2 = inconsistent
  int pad = 0;
};

struct ListEntry // one candidate of the compacted list
{
  unsigned bits;
  unsigned pad;
  long long index;
};

constexpr long long kFastListCapacity = 1 << 16;

// The row maxima of a score volume of slices of nx x ny (HarrisKernelArgs::rowMax): for
// each pair of rows (2 p, 2 p + 1) of a slice, segmentsPerRow segments of 32 columns (the
// last one may be narrower), each with the largest candidate's bit pattern in it (0: none),
// at (slice * ((ny + 1) / 2) + p) * segmentsPerRow + segment.
struct RowMaxima
{
  const unsigned* max = nullptr;
  int nx = 0, ny = 0;
  int segmentsPerRow = 0;
};

class TopNSelector : NonCopyable
{
public:
  TopNSelector() = default;
  ~TopNSelector();

  // The level-1 histogram (kLevel1Bins counters) that the Harris kernel fills.
  unsigned long long* level1Histogram() const { return Hist; }
  // Allocates the buffers for N points (kept between calls) and zeroes the histograms and
  // the selection state on `stream`. Call before the level-1 histogram is filled.
  bool reset(int N, cudaStream_t stream, std::string* error);
  // Level-1 histogram of a score volume already on the device (when it was not fused).
  bool histogramLevel1(const float* scores, std::size_t n, cudaStream_t stream, std::string* error);
  // Selection from `n` device scores whose level-1 histogram is complete. `beforeDownload`
  // and `afterDownload` (optional) are recorded around the copy of the N results. `rows`
  // (optional): the scores' row maxima, complete (n a multiple of rows->nx * rows->ny),
  // which the fast path's compaction reads instead of every score.
  bool select(const float* scores, std::size_t n, int N, cudaStream_t stream, InterestPoints& out,
    std::string* error, cudaEvent_t beforeDownload = nullptr, cudaEvent_t afterDownload = nullptr,
    const RowMaxima* rows = nullptr);
  void release();

  // Entries of the last selection's compacted list and whether it took the slow path.
  long long lastListSize() const { return LastListSize; }
  bool lastUsedSlowPath() const { return LastSlow; }
  // Test hook: force the slow path.
  void setForceSlowPath(bool force) { ForceSlow = force; }
  // The scores are valid only in the blocks the Harris kernel computed (pruned, with their
  // row maxima): select() then reads no other score. Where it would (the slow path, or no
  // row maxima), it returns false with lastNeedsCompleteScores() set, and no error.
  void setScoresPartial(bool partial) { Partial = partial; }
  bool lastNeedsCompleteScores() const { return LastNeedsComplete; }

private:
  bool selectSlow(const float* scores, std::size_t n, int N, cudaStream_t stream, std::string* error);
  bool finish(int N, bool takeAll, unsigned long long total, InterestPoints& out, std::string* error);
  template <typename T>
  bool grow(T*& buffer, std::size_t& capacity, std::size_t wanted, std::string* error);

  unsigned long long* Hist = nullptr; // levels 1, 2, 3: 2048 + 2048 + 1024
  // One device block copied back in one transfer: sorted values (N), sorted keys (N), the
  // state, the CUB counts (list, above, ties); HostResult is its pinned mirror.
  unsigned char* Result = nullptr;
  unsigned char* HostResult = nullptr;
  std::size_t ResultBytes = 0;
  int ResultN = 0;
  SelectState* State = nullptr;
  long long* Counts = nullptr;
  ListEntry* FastList = nullptr;
  long long* ListIdx = nullptr;
  unsigned* ListBits = nullptr;
  long long* TiePos = nullptr;
  std::size_t ListCap = 0, ListBitsCap = 0, TieCap = 0;
  long long* AbovePos = nullptr;
  unsigned* KeysIn = nullptr;
  unsigned* KeysOut = nullptr; // in Result
  long long* ValsIn = nullptr;
  long long* ValsOut = nullptr; // in Result
  std::size_t AboveCap = 0, KeysInCap = 0, ValsInCap = 0;
  unsigned char* Temp = nullptr;
  std::size_t TempCap = 0;
  int SmCount = 0;
  long long LastListSize = 0;
  bool LastSlow = false;
  bool ForceSlow = false;
  bool Partial = false;
  bool LastNeedsComplete = false;
};

} // namespace detail
} // namespace cuda
} // namespace mcv
