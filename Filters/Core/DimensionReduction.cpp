// The dimension-reduction entry point: checks, column selection, reference sample, fit,
// out-of-sample placement of every row, trustworthiness, timings and progress.
#include "DimensionReduction.h"

#include "IsomapEmbedding.h"
#include "LLEEmbedding.h"
#include "OutOfSample.h"
#include "PCAEmbedding.h"
#include "ReferenceSample.h"
#include "Trustworthiness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <new>
#include <numeric>

namespace mcv
{

namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

const char* methodName(ReductionMethod m)
{
  switch (m)
  {
    case ReductionMethod::PCA:
      return "PCA";
    case ReductionMethod::Isomap:
      return "Isomap";
    case ReductionMethod::LLE:
      return "LLE";
  }
  return "unknown";
}

struct ColumnStats
{
  std::vector<double> mean, minimum, maximum;
  std::size_t nonFinite = 0;
  std::size_t firstBadRow = 0;
  int firstBadColumn = 0;
};

// One pass over the matrix in fixed blocks combined in order (deterministic, any threads).
ColumnStats columnStats(const FeatureMatrix& f)
{
  const int D = f.cols;
  const std::size_t blockSize = 1 << 15;
  const std::size_t blocks = (f.rows + blockSize - 1) / blockSize;
  std::vector<ColumnStats> partial(blocks);
  const long long nb = static_cast<long long>(blocks);
#pragma omp parallel for schedule(dynamic, 1)
  for (long long b = 0; b < nb; ++b)
  {
    ColumnStats& s = partial[static_cast<std::size_t>(b)];
    s.mean.assign(D, 0.0);
    s.minimum.assign(D, std::numeric_limits<double>::infinity());
    s.maximum.assign(D, -std::numeric_limits<double>::infinity());
    const std::size_t begin = static_cast<std::size_t>(b) * blockSize;
    const std::size_t end = std::min(f.rows, begin + blockSize);
    for (std::size_t i = begin; i < end; ++i)
    {
      const float* row = f.row(i);
      for (int c = 0; c < D; ++c)
      {
        const float v = row[c];
        if (!std::isfinite(v))
        {
          if (s.nonFinite++ == 0)
          {
            s.firstBadRow = i;
            s.firstBadColumn = c;
          }
          continue;
        }
        s.mean[c] += v;
        s.minimum[c] = std::min<double>(s.minimum[c], v);
        s.maximum[c] = std::max<double>(s.maximum[c], v);
      }
    }
  }
  ColumnStats total;
  total.mean.assign(D, 0.0);
  total.minimum.assign(D, std::numeric_limits<double>::infinity());
  total.maximum.assign(D, -std::numeric_limits<double>::infinity());
  for (const ColumnStats& s : partial)
  {
    if (s.nonFinite > 0 && total.nonFinite == 0)
    {
      total.firstBadRow = s.firstBadRow;
      total.firstBadColumn = s.firstBadColumn;
    }
    total.nonFinite += s.nonFinite;
    for (int c = 0; c < D; ++c)
    {
      total.mean[c] += s.mean[c];
      total.minimum[c] = std::min(total.minimum[c], s.minimum[c]);
      total.maximum[c] = std::max(total.maximum[c], s.maximum[c]);
    }
  }
  for (double& m : total.mean)
  {
    m /= static_cast<double>(f.rows);
  }
  return total;
}

ReductionResult reduce(const FeatureMatrix& features, const ReductionOptions& options)
{
  const auto start = Clock::now();
  ReductionResult result;
  auto fail = [&](std::string message) {
    result.error = std::move(message);
    result.coordinates.clear();
    return result;
  };
  auto report = [&](const char* stage, double f) {
    if (options.progress)
    {
      options.progress(stage, std::min(1.0, std::max(0.0, f)));
    }
  };
  // Progress of a stage mapped into [lo, hi] of the whole.
  auto within = [&](double lo, double hi) {
    return [&, lo, hi](const char* stage, double f) { report(stage, lo + (hi - lo) * f); };
  };

  // --- Checks -------------------------------------------------------------------------
  const int d = options.outputDimension;
  if (d != 2 && d != 3)
  {
    return fail("OutputDimension must be 2 or 3 (got " + std::to_string(d) + ").");
  }
  if (options.method != ReductionMethod::PCA && options.method != ReductionMethod::Isomap &&
    options.method != ReductionMethod::LLE)
  {
    return fail("Unknown reduction method " + std::to_string(static_cast<int>(options.method)) + ".");
  }
  if (features.data == nullptr || features.rows == 0)
  {
    return fail("The feature array has no rows (no voxels): nothing to reduce.");
  }
  if (features.cols < 2)
  {
    return fail("The feature array has " + std::to_string(features.cols) +
      " component(s): nothing to reduce (at least 2 features are needed).");
  }
  const bool graphMethod = options.method != ReductionMethod::PCA;
  if (graphMethod && options.numberOfNeighbors < 1)
  {
    return fail("NumberOfNeighbors must be at least 1 (got " + std::to_string(options.numberOfNeighbors) + ").");
  }
  if (options.method == ReductionMethod::Isomap && options.numberOfLandmarks < 1)
  {
    return fail("NumberOfLandmarks must be at least 1 (got " + std::to_string(options.numberOfLandmarks) + ").");
  }
  if (options.referenceSampleSize == 0)
  {
    return fail("ReferenceSampleSize must be at least 1.");
  }
  result.outputDimension = d;
  report("Checking features", 0.0);

  // NaN/Inf are an error: they have no place in a distance, and silently dropping voxels
  // would leave holes in the output. The message says where the first one is.
  const ColumnStats stats = columnStats(features);
  if (stats.nonFinite > 0)
  {
    return fail("The features contain " + std::to_string(stats.nonFinite) +
      " non-finite value(s) (NaN or Inf), the first at voxel " + std::to_string(stats.firstBadRow) + ", component " +
      std::to_string(stats.firstBadColumn) + "; replace or mask them before reducing.");
  }
  std::vector<int> used;
  std::vector<double> usedMean;
  std::string dropped;
  for (int c = 0; c < features.cols; ++c)
  {
    const double range = stats.maximum[c] - stats.minimum[c];
    const double scale = std::max(std::abs(stats.maximum[c]), std::abs(stats.minimum[c]));
    if (range <= 1e-7 * scale || range == 0.0)
    {
      dropped += (dropped.empty() ? "" : ", ") + std::to_string(c);
      continue;
    }
    used.push_back(c);
    usedMean.push_back(stats.mean[c]);
  }
  if (!dropped.empty())
  {
    result.warnings.push_back("Constant feature component(s) " + dropped +
      " (zero variance) carry no information and were left out.");
  }
  if (used.size() < 2)
  {
    return fail("Only " + std::to_string(used.size()) + " of the " + std::to_string(features.cols) +
      " feature components vary: nothing to reduce.");
  }
  result.usedColumns = used;
  const bool allColumns = static_cast<int>(used.size()) == features.cols;
  const std::vector<int> gatherColumns = allColumns ? std::vector<int>{} : used;

  std::string deviceWarning;
  const Device device = resolveDevice(options.device, &deviceWarning);
  if (!deviceWarning.empty())
  {
    result.warnings.push_back(deviceWarning);
  }
  result.deviceUsed = Device::CPU; // the placement below says where it really ran

  // --- Reference sample ---------------------------------------------------------------
  report("Drawing the reference sample", 0.03);
  if (options.referenceSampleSize > features.rows)
  {
    result.warnings.push_back("ReferenceSampleSize (" + std::to_string(options.referenceSampleSize) +
      ") exceeds the number of voxels (" + std::to_string(features.rows) + "); the embedding is fitted on all of them.");
  }
  ReferenceSampleOptions so;
  so.size = options.referenceSampleSize;
  so.seed = options.randomSeed;
  result.referenceIndices = drawReferenceSample(features.data, features.rows, features.cols, used, usedMean, so);
  const std::size_t M = result.referenceIndices.size();
  const std::size_t wanted = std::min(options.referenceSampleSize, features.rows);
  if (M < wanted)
  {
    result.warnings.push_back("Only " + std::to_string(M) + " distinct feature vectors were found for a reference sample of " +
      std::to_string(wanted) + " (identical voxels are fitted once).");
  }
  if (graphMethod && static_cast<std::size_t>(options.numberOfNeighbors) >= M)
  {
    return fail("NumberOfNeighbors (" + std::to_string(options.numberOfNeighbors) +
      ") must be less than the number of distinct reference points (" + std::to_string(M) +
      "); lower it or raise ReferenceSampleSize.");
  }
  if (M < static_cast<std::size_t>(d) + 2)
  {
    return fail("Only " + std::to_string(M) + " distinct feature vectors: at least " + std::to_string(d + 2) +
      " are needed for a " + std::to_string(d) + "D embedding.");
  }
  const Eigen::Index D = static_cast<Eigen::Index>(used.size());
  RowMatrixF refX(static_cast<Eigen::Index>(M), D);
  for (std::size_t r = 0; r < M; ++r)
  {
    const float* row = features.row(static_cast<std::size_t>(result.referenceIndices[r]));
    for (Eigen::Index c = 0; c < D; ++c)
    {
      refX(static_cast<Eigen::Index>(r), c) = row[used[static_cast<std::size_t>(c)]];
    }
  }

  // --- Fit ----------------------------------------------------------------------------
  const auto fitStart = Clock::now();
  Embedding embedding;
  PCAModel pca;
  switch (options.method)
  {
    case ReductionMethod::PCA:
      report("PCA", 0.05);
      embedding = fitPCA(refX.data(), M, static_cast<int>(D), {}, {}, d, &pca);
      break;
    case ReductionMethod::Isomap:
    {
      IsomapOptions io;
      io.outputDimension = d;
      io.numberOfNeighbors = options.numberOfNeighbors;
      io.numberOfLandmarks = options.numberOfLandmarks;
      io.seed = options.randomSeed;
      io.progress = within(0.05, 0.6);
      embedding = fitIsomap(refX, io);
      break;
    }
    case ReductionMethod::LLE:
    {
      LLEOptions lo;
      lo.outputDimension = d;
      lo.numberOfNeighbors = options.numberOfNeighbors;
      lo.progress = within(0.05, 0.6);
      embedding = fitLLE(refX, lo);
      break;
    }
  }
  result.fitMs = msSince(fitStart);
  for (auto& w : embedding.warnings)
  {
    result.warnings.push_back(w);
  }
  if (!embedding.error.empty())
  {
    return fail(embedding.error);
  }
  if (!embedding.coordinates.allFinite())
  {
    return fail(std::string(methodName(options.method)) +
      ": the embedding has non-finite coordinates (degenerate data); try more neighbours or another method.");
  }
  result.eigenvalues = embedding.eigenvalues;
  result.varianceRetained = embedding.varianceRetained;

  // --- Every voxel ----------------------------------------------------------------------
  const auto placeStart = Clock::now();
  result.coordinates.resize(features.rows * static_cast<std::size_t>(d));
  if (options.method == ReductionMethod::PCA)
  {
    report("PCA projection", 0.6);
    if (options.device == Device::GPU)
    {
      result.warnings.push_back("The PCA projection (a small matrix product per voxel) runs on the CPU.");
    }
    projectPCA(pca, features.data, features.rows, features.cols, gatherColumns, result.coordinates.data());
  }
  else
  {
    OutOfSampleOptions oo;
    oo.device = device;
    oo.progress = within(0.6, 0.95);
    const OutOfSampleReport placed = placeOutOfSample(refX, embedding.coordinates, features.data, features.rows,
      features.cols, allColumns ? std::vector<int>{} : used, result.coordinates.data(), oo);
    result.deviceUsed = placed.deviceUsed;
    result.warnings.insert(result.warnings.end(), placed.warnings.begin(), placed.warnings.end());
  }
  result.placeMs = msSince(placeStart);

  // --- Trustworthiness on a sample of the reference points ----------------------------
  report("Trustworthiness", 0.95);
  const std::size_t nt = std::min(options.trustworthinessSample, M);
  const int k = options.trustworthinessNeighbors;
  result.trustworthiness = std::numeric_limits<double>::quiet_NaN();
  if (nt == 0)
  {
    // not asked for
  }
  else if (k < 1 || 2 * static_cast<std::size_t>(k) >= nt)
  {
    result.warnings.push_back("Trustworthiness not computed: k = " + std::to_string(k) +
      " needs a sample of more than 2k points (have " + std::to_string(nt) + ").");
  }
  else
  {
    std::vector<std::int64_t> pick(M);
    std::iota(pick.begin(), pick.end(), std::int64_t(0));
    std::uint64_t state = options.randomSeed ^ 0x7457ull;
    for (std::size_t i = 0; i < nt; ++i)
    {
      std::swap(pick[i], pick[i + static_cast<std::size_t>(uniformIndex(state, M - i))]);
    }
    pick.resize(nt);
    std::sort(pick.begin(), pick.end());
    RowMatrixF tx(static_cast<Eigen::Index>(nt), D);
    RowMatrixF ty(static_cast<Eigen::Index>(nt), d);
    for (std::size_t i = 0; i < nt; ++i)
    {
      tx.row(static_cast<Eigen::Index>(i)) = refX.row(pick[i]);
      ty.row(static_cast<Eigen::Index>(i)) = embedding.coordinates.row(pick[i]);
    }
    result.trustworthiness = trustworthiness(tx.data(), static_cast<int>(D), ty.data(), d, nt, k);
  }
  result.totalMs = msSince(start);
  report("Done", 1.0);
  return result;
}
} // namespace

ReductionResult reduceDimension(const FeatureMatrix& features, const ReductionOptions& options)
{
  try
  {
    return reduce(features, options);
  }
  catch (const std::bad_alloc&)
  {
    ReductionResult r;
    r.error = "Out of memory in the dimension reduction; lower ReferenceSampleSize or NumberOfLandmarks.";
    return r;
  }
  catch (const std::exception& e)
  {
    ReductionResult r;
    r.error = std::string("Dimension reduction failed: ") + e.what();
    return r;
  }
}

} // namespace mcv
