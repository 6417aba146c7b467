// The reference sample the embedding is fitted on (dissertation section 5.4.2): M voxels,
// seeded, with distinct feature vectors; the same voxels whether the volume is reduced by
// one process or split over several (Communicator.h, GridPiece.h).
//
// Scheme (norm-stratified, so rare bright structures are kept):
//  - every voxel gets a random 64-bit key from (seed, global index) by a counter-based hash,
//    so no choice depends on the order rows are visited in, nor on the split; and the
//    Euclidean norm of its (used, centred) feature vector;
//  - exact duplicates (many background voxels share one feature vector) are drawn once: a
//    duplicate adds nothing to the fit and would break kNN graphs (zero distances). A
//    distinct vector stands for all its voxels with the key of its lowest-keyed voxel;
//  - 8 strata of the norm whose upper quantile edges halve towards the top: [0, .5),
//    [.5, .75), [.75, .875), ... , [.9921875, 1]; the quantiles are measured on the voxels
//    whose key is below a threshold (about 65536 of them; all voxels of a smaller volume);
//  - half of the sample is shared equally among the strata: in each, the distinct vectors
//    with the smallest keys. The top 0.8 % of voxels by norm (the bright, high-gradient
//    ones a user looks for) thus get 1/16 of the sample instead of 0.8 % of it;
//  - the rest is uniform (keeps the density: what is common in the volume is common in the
//    domain): the distinct vectors with the smallest keys among those not yet taken.
// When fewer distinct vectors exist than asked for, all of them are returned.
// Rows marked 0 in ReferenceSampleOptions::eligible (the background of a volume) are never
// drawn and count in no stratum: the sample is that of the eligible voxels alone.
//
// Split over processes, no process sees all voxels: each proposes its own candidates in key
// order, all gather the candidates (O(M) vectors), merge them by key and, while the merged
// lists cannot decide yet, ask every process for more.
#pragma once

#include "Communicator.h"
#include "FeatureRows.h"
#include "GridPiece.h"
#include "ImageGrid.h"

#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <new>
#include <string>
#include <utility>
#include <vector>

namespace mcv
{

// The rows one process holds: their indices in the whole data set (global indices) and
// which of them it owns (counts). Either plain rows (a matrix with no grid) or the voxels of
// a block of a volume (x fastest).
class RowLayout
{
public:
  // n rows, all owned, global index = first + row.
  static RowLayout plain(std::size_t n, std::int64_t first = 0);
  // The voxels of `block`, placed in the volume and owned as `piece` says. With steps > 1,
  // the rows are `steps` such blocks one after another (the time steps of a series, each
  // block split alike), and step s's voxels have global index s x (whole voxels) + voxel.
  static RowLayout grid(const GridPiece& piece, const ImageGrid& block, int steps = 1);

  std::size_t size() const { return rows_; }
  std::size_t ownedCount() const;

  // The owned rows come in runs of consecutive rows with consecutive global indices (a line
  // of the owned box along x, or a chunk of plain rows): the loops go run by run.
  struct Run
  {
    std::size_t row = 0;     // first row
    std::int64_t global = 0; // its global index
    std::size_t count = 0;
  };
  std::size_t runCount() const;
  Run run(std::size_t r) const;
  // The runs [first, last) holding rows of [begin, end) (runs ascend by row): a pass over
  // the blocks of a FeatureRows visits only these per block; every run for every block
  // made such a pass cost blocks x rows (33 slabs x 1 G voxels).
  std::pair<std::size_t, std::size_t> runsWithin(std::size_t begin, std::size_t end) const;

private:
  std::size_t rows_ = 0;
  bool grid_ = false;
  std::int64_t first_ = 0;
  GridPiece piece_;
  ImageGrid block_;
  int steps_ = 1;
  // Of one step (grid layouts): its runs, and its rows and global indices.
  std::size_t stepRuns() const;
};

struct ReferenceSampleOptions
{
  std::size_t size = 10000;
  std::uint64_t seed = 0;
  int strata = 8;
  double stratifiedFraction = 0.5; // of the sample shared equally among the strata
  // Optional, one byte per row of this process (RowLayout::size()): 0 = never drawn. Null:
  // every owned row may be drawn.
  const unsigned char* eligible = nullptr;
  // Optional: the pass over the source's blocks (the strata) reports its fraction here, on
  // the calling thread, before each block (FeatureRows with several blocks only).
  std::function<void(double)> progress;
  // The passes over every row on the GPU: the strata on the source's device
  // (FeatureRows::strataOnDevice) when it has one, the key scans in a CUDA build (a failure
  // falls back to the CPU with a warning). A serial caller whose process owns every row sets
  // it (reduceDimension on the GPU).
  bool onDevice = false;
};

struct ReferenceSample
{
  std::string error;                 // non-empty: nothing else is meaningful
  std::vector<std::string> warnings; // e.g. the device's strata pass failed and the CPU's ran
  std::vector<std::int64_t> indices; // global indices, ascending
  std::vector<float> vectors;        // indices.size() x columns.size(): the used features
};

// Collective over `comm` (null: serial). `data` is rows.size() x dim row-major; `columns`
// the columns used (empty: all), `center` their mean (empty: no centring). Every process
// gets the same sample, with the feature vectors of its voxels.
ReferenceSample drawReferenceSample(const float* data, int dim, const RowLayout& rows,
  const std::vector<int>& columns, const std::vector<double>& center, const ReferenceSampleOptions& options,
  const Communicator* comm);

// The same, reading the features from `source` (rows: source.rows(), dim: source.cols()):
// a pass over its blocks for the strata, gathers of the few rows it looks at otherwise.
ReferenceSample drawReferenceSample(FeatureRows& source, const RowLayout& rows, const std::vector<int>& columns,
  const std::vector<double>& center, const ReferenceSampleOptions& options, const Communicator* comm);

// Serial: `data` is n x dim row-major. Returns sorted row indices of distinct feature
// vectors; when size >= n every distinct row is returned.
std::vector<std::int64_t> drawReferenceSample(const float* data, std::size_t n, int dim,
  const std::vector<int>& columns, const std::vector<double>& center, const ReferenceSampleOptions& options);

// This process's owned rows that `eligible` (ReferenceSampleOptions::eligible; null:
// every row) lets the sample draw.
std::size_t eligibleCount(const RowLayout& rows, const unsigned char* eligible);

// The random key of a voxel: a bijection of the global index for a given seed (keys never
// tie), uniform over 64 bits.
std::uint64_t sampleKey(std::uint64_t seed, std::int64_t globalIndex);

// L distinct indices of [0, n) drawn uniformly (seeded partial Fisher-Yates): the landmarks
// of landmark Isomap and of locally linear landmarks. Uniform, not MaxMin (farthest point):
// MaxMin spends the landmarks on the outliers of z-scored features and leaves the dense core
// to be triangulated from far away; on the brain's features it lost 0.012 (6D, N = 5000)
// and 0.021 (24D, N = 10000) of trustworthiness against exact Isomap over three seeds, where
// uniform landmarks scatter around it (compare_sklearn.py). L <= n.
std::vector<std::uint32_t> uniformLandmarks(std::size_t n, int L, std::uint64_t seed);

// Collective: the error of the first process (in rank order) that has one, on every
// process; empty when none has. Lets all processes stop together instead of some of them
// waiting in the next collective for one that gave up.
std::string sharedError(const Communicator* comm, const std::string& localError);

// Runs `work` (local: no collective inside) and shares its failure as sharedError does:
// an exception on one process becomes the same error on all of them (null comm: the
// exception's text, worded as reduceDimension words it).
template <class Work>
std::string runShared(const Communicator* comm, Work&& work)
{
  std::string error;
  try
  {
    work();
  }
  catch (const std::bad_alloc&)
  {
    error = "Out of memory in the dimension reduction; lower ReferenceSampleSize or NumberOfLandmarks.";
  }
  catch (const std::exception& e)
  {
    error = std::string("Dimension reduction failed: ") + e.what();
  }
  return sharedError(comm, error);
}

} // namespace mcv
