// The dimension-reduction entry point: checks, column selection, reference sample, fit,
// out-of-sample placement of every row, trustworthiness, timings and progress. Split over
// processes, the global steps (column statistics, the sample, the fit) go through the
// Communicator and give every process the answer one process would give; the placement of
// each process's rows is local.
#include "DimensionReduction.h"

#include "HalfCoordinates.h"
#include "KeptRows.h"
#include "ModelDistance.h"
#include "OutOfSample.h"
#include "PCAEmbedding.h"
#include "ReductionMethods.h"
#include "ReferenceSample.h"
#include "SeededRandom.h"
#include "Trustworthiness.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <new>
#include <numeric>
#include <string>
#include <thread>

namespace mcv
{

namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// ---- Where the rows lie ------------------------------------------------------------------

bool hasGrid(const ReductionOptions& o)
{
  const std::array<int, 3>& w = o.piece.wholeDims;
  return w[0] != 0 || w[1] != 0 || w[2] != 0;
}

std::string dimsText(const std::array<int, 3>& d)
{
  return std::to_string(d[0]) + " x " + std::to_string(d[1]) + " x " + std::to_string(d[2]);
}

// This process's rows against their description (local): an error when they do not fit.
std::string checkRows(const FeatureRows& f, const ReductionOptions& o)
{
  if (!hasGrid(o))
  {
    return {};
  }
  const GridPiece& p = o.piece;
  const ImageGrid& b = o.block;
  if (b.voxelCount() * static_cast<std::size_t>(std::max(o.timeSteps, 1)) != f.rows())
  {
    return "The block of " + dimsText(b.dims) + " voxels does not match the " + std::to_string(f.rows()) +
      " feature rows.";
  }
  for (int a = 0; a < 3; ++a)
  {
    if (b.dims[a] < 0 || p.offset[a] < 0 || p.offset[a] + b.dims[a] > p.wholeDims[a])
    {
      return "The block of " + dimsText(b.dims) + " voxels at offset " + dimsText(p.offset) +
        " lies outside the whole volume of " + dimsText(p.wholeDims) + " voxels.";
    }
    if (p.ownedCount() > 0 && (p.ownedLo[a] < 0 || p.ownedHi[a] >= b.dims[a]))
    {
      return "The owned voxels " + dimsText(p.ownedLo) + " to " + dimsText(p.ownedHi) + " lie outside the block of " +
        dimsText(b.dims) + " voxels.";
    }
  }
  const bool boxSet = o.outputLo[0] <= o.outputHi[0] && o.outputLo[1] <= o.outputHi[1] && o.outputLo[2] <= o.outputHi[2];
  for (int a = 0; a < 3 && boxSet; ++a)
  {
    if (o.outputLo[a] < 0 || o.outputHi[a] >= b.dims[a])
    {
      return "The output box " + dimsText(o.outputLo) + " to " + dimsText(o.outputHi) + " lies outside the block of " +
        dimsText(b.dims) + " voxels.";
    }
  }
  return {};
}

// The rows the coordinates output holds (ReductionOptions::outputLo/outputHi).
KeptRows keptRows(const ReductionOptions& o, std::size_t rows)
{
  return hasGrid(o) ? KeptRows(o.block.dims, o.outputLo, o.outputHi) : KeptRows(rows);
}

// Collective: the processes must agree on the number of features and on the volume, or their
// statistics would not add up. Empty when they do.
std::string checkAgreement(const FeatureRows& f, const ReductionOptions& o, const Communicator* comm)
{
  if (!isDistributed(comm))
  {
    return {};
  }
  const std::vector<double> mine{ static_cast<double>(f.cols()), hasGrid(o) ? 1.0 : 0.0,
    static_cast<double>(o.piece.wholeDims[0]), static_cast<double>(o.piece.wholeDims[1]),
    static_cast<double>(o.piece.wholeDims[2]), o.sampleMask ? 1.0 : 0.0 };
  std::vector<double> lowest = mine, highest = mine;
  comm->min(lowest);
  comm->max(highest);
  if (lowest[0] != highest[0])
  {
    return "The processes' feature arrays have different numbers of components (" +
      std::to_string(static_cast<int>(lowest[0])) + " to " + std::to_string(static_cast<int>(highest[0])) + ").";
  }
  if (lowest[5] != highest[5])
  {
    return "Some processes have a foreground mask (sampleMask) and others not.";
  }
  if (lowest != highest)
  {
    return "The processes describe their rows differently (some as blocks of a volume, some not, or of volumes of "
           "different sizes).";
  }
  return {};
}

// The rows' layout. Plain rows of several processes follow one another in rank order
// (collective then).
RowLayout makeLayout(const FeatureRows& f, const ReductionOptions& o, const Communicator* comm)
{
  if (hasGrid(o))
  {
    return RowLayout::grid(o.piece, o.block, o.timeSteps);
  }
  std::int64_t first = 0;
  if (isDistributed(comm))
  {
    const std::vector<std::uint64_t> rows = allGatherValues(*comm, std::vector<std::uint64_t>{ f.rows() });
    for (int r = 0; r < comm->rank(); ++r)
    {
      first += static_cast<std::int64_t>(rows[static_cast<std::size_t>(r)]);
    }
  }
  return RowLayout::plain(f.rows(), first);
}

// ---- Column statistics -----------------------------------------------------------------

// Sums of floats that are exact, hence the same in any order and for any split of the
// volume (so is the mean, and with it every voxel's centred norm): a float is m 2^(e - 150)
// with an integer |m| < 2^24 and e its exponent field, so integer sums per exponent lose
// nothing (up to 2^39 values).
constexpr int kExponents = 256;

void addExact(std::int64_t* bins, float v)
{
  std::uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const int e = static_cast<int>((bits >> 23) & 0xFFu);
  const std::int64_t m = static_cast<std::int64_t>((bits & 0x7FFFFFu) | (e != 0 ? 0x800000u : 0u));
  bins[std::max(e, 1)] += (bits >> 31) != 0 ? -m : m;
}

double exactValue(const std::int64_t* bins)
{
  double s = 0;
  for (int e = 0; e < kExponents; ++e)
  {
    s += std::ldexp(static_cast<double>(bins[e]), e - 150);
  }
  return s;
}

// Adds the bins of all processes exactly: a bin travels as two doubles holding integers
// below 2^53 (its high part and its low 24 bits), whose sums are exact in any order.
void sumExact(std::vector<std::int64_t>& bins, const Communicator& comm)
{
  const std::int64_t unit = std::int64_t(1) << 24;
  std::vector<double> parts(2 * bins.size());
  for (std::size_t i = 0; i < bins.size(); ++i)
  {
    const std::int64_t low = bins[i] & (unit - 1);
    parts[2 * i] = static_cast<double>((bins[i] - low) / unit);
    parts[2 * i + 1] = static_cast<double>(low);
  }
  comm.sum(parts);
  for (std::size_t i = 0; i < bins.size(); ++i)
  {
    bins[i] = static_cast<std::int64_t>(parts[2 * i]) * unit + static_cast<std::int64_t>(parts[2 * i + 1]);
  }
}

struct ColumnStats
{
  std::vector<std::int64_t> bins; // cols x kExponents: exact sums
  std::vector<double> mean, minimum, maximum;
  double nonFinite = 0;
  // The first non-finite value in the volume's order, as global voxel x cols + column.
  double firstBad = std::numeric_limits<double>::infinity();

  explicit ColumnStats(int D)
    : bins(static_cast<std::size_t>(D) * kExponents, 0)
    , mean(static_cast<std::size_t>(D), 0.0)
    , minimum(static_cast<std::size_t>(D), std::numeric_limits<double>::infinity())
    , maximum(static_cast<std::size_t>(D), -std::numeric_limits<double>::infinity())
  {
  }
  void merge(const ColumnStats& o)
  {
    for (std::size_t i = 0; i < bins.size(); ++i)
    {
      bins[i] += o.bins[i];
    }
    for (std::size_t c = 0; c < minimum.size(); ++c)
    {
      minimum[c] = std::min(minimum[c], o.minimum[c]);
      maximum[c] = std::max(maximum[c], o.maximum[c]);
    }
    nonFinite += o.nonFinite;
    firstBad = std::min(firstBad, o.firstBad);
  }
};

// One pass over the owned rows, block by block. Every combination is exact or a min/max, so
// neither the threads, the blocks nor the split change the result.
// `progress` (optional) hears of each block, so that a long fused pass can be followed and
// aborted.
ColumnStats localStats(FeatureRows& f, const RowLayout& rows, const std::function<void(double)>& progress)
{
  const int D = f.cols();
  ColumnStats total(D);
  for (std::size_t b = 0; b < f.blockCount(); ++b)
  {
    if (progress && f.blockCount() > 1)
    {
      progress(static_cast<double>(b) / static_cast<double>(f.blockCount()));
    }
    const std::size_t begin = f.blockBegin(b), end = f.blockBegin(b + 1);
    const float* block = f.block(b);
    const std::pair<std::size_t, std::size_t> within = rows.runsWithin(begin, end);
    const long long first = static_cast<long long>(within.first), last = static_cast<long long>(within.second);
#pragma omp parallel
  {
    ColumnStats mine(D);
#pragma omp for schedule(static) nowait
    for (long long r = first; r < last; ++r)
    {
      const RowLayout::Run run = rows.run(static_cast<std::size_t>(r));
      const std::size_t from = std::max(run.row, begin) - run.row, to = std::min(run.row + run.count, end) - run.row;
      for (std::size_t t = from; t < to; ++t)
      {
        const float* row = block + (run.row + t - begin) * static_cast<std::size_t>(D);
        for (int c = 0; c < D; ++c)
        {
          const float v = row[c];
          if (!std::isfinite(v))
          {
            mine.nonFinite += 1;
            mine.firstBad = std::min(mine.firstBad,
              static_cast<double>(run.global + static_cast<std::int64_t>(t)) * D + c);
            continue;
          }
          addExact(&mine.bins[static_cast<std::size_t>(c) * kExponents], v);
          mine.minimum[c] = std::min<double>(mine.minimum[c], v);
          mine.maximum[c] = std::max<double>(mine.maximum[c], v);
        }
      }
    }
#pragma omp critical(mcvColumnStats)
    total.merge(mine);
  }
  }
  return total;
}

// The same statistics from the rows' own device pass (FeatureRows::columnSumsOnDevice; every
// row owned): false when there is none or it failed (said in `warnings`), so the caller
// walks the blocks.
bool deviceColumnStats(FeatureRows& f, const std::function<void(double)>& progress, ColumnStats& stats,
  std::vector<std::string>& warnings)
{
  DeviceColumnSums sums = f.columnSumsOnDevice(progress);
  if (!sums.attempted)
  {
    return false;
  }
  if (!sums.error.empty() || sums.bins.size() != stats.bins.size() || sums.minimum.size() != stats.minimum.size() ||
    sums.maximum.size() != stats.maximum.size())
  {
    warnings.push_back("The GPU column statistics failed (" + (sums.error.empty() ? std::string("unexpected result") : sums.error) +
      "); they ran on the CPU.");
    return false;
  }
  stats.bins = std::move(sums.bins);
  stats.minimum = std::move(sums.minimum);
  stats.maximum = std::move(sums.maximum);
  stats.nonFinite = sums.nonFinite;
  stats.firstBad = sums.firstBad;
  return true;
}

// Collective: the statistics of all processes' owned rows, the same on every process.
void combineStats(ColumnStats& s, double voxels, const Communicator* comm)
{
  if (isDistributed(comm))
  {
    std::vector<double> lowest = s.minimum;
    lowest.push_back(s.firstBad);
    comm->min(lowest);
    s.firstBad = lowest.back();
    lowest.pop_back();
    s.minimum = lowest;
    comm->max(s.maximum);
    std::vector<double> count{ s.nonFinite };
    comm->sum(count);
    s.nonFinite = count[0];
    sumExact(s.bins, *comm);
  }
  for (std::size_t c = 0; c < s.mean.size(); ++c)
  {
    s.mean[c] = exactValue(&s.bins[c * kExponents]) / voxels;
  }
}

// Collective: the voxels of all processes the sample may draw (`mask` null: all N).
std::size_t sampleableVoxels(const RowLayout& rows, const unsigned char* mask, std::size_t N, const Communicator* comm)
{
  if (!mask)
  {
    return N;
  }
  std::vector<double> count{ static_cast<double>(eligibleCount(rows, mask)) };
  if (isDistributed(comm))
  {
    comm->sum(count);
  }
  return static_cast<std::size_t>(count[0]);
}

// ---- The fit: on process 0, shared with the others ------------------------------------------

struct Fit
{
  std::string error;
  std::vector<std::string> warnings;
  RowMatrixF coordinates; // M x d: the reference points' embedding
  std::vector<double> eigenvalues;
  double varianceRetained = 0.0;
  double trustworthiness = std::numeric_limits<double>::quiet_NaN();
  double ms = 0.0;
  PCAModel pca;
  double referenceRadius = 0.0; // ModelDistance.h
};

// Trustworthiness on a seeded sample of the reference points (NaN when not measured).
void measureTrustworthiness(const RowMatrixF& refX, const ReductionOptions& options, Fit& fit)
{
  const std::size_t M = static_cast<std::size_t>(refX.rows());
  const std::size_t nt = std::min(options.trustworthinessSample, M);
  const int k = options.trustworthinessNeighbors;
  if (nt == 0)
  {
    return; // not asked for
  }
  if (k < 1 || 2 * static_cast<std::size_t>(k) >= nt)
  {
    fit.warnings.push_back("Trustworthiness not computed: k = " + std::to_string(k) +
      " needs a sample of more than 2k points (have " + std::to_string(nt) + ").");
    return;
  }
  std::vector<std::int64_t> pick(M);
  std::iota(pick.begin(), pick.end(), std::int64_t(0));
  std::uint64_t state = options.randomSeed ^ 0x7457ull;
  for (std::size_t i = 0; i < nt; ++i)
  {
    std::swap(pick[i], pick[i + static_cast<std::size_t>(uniformIndex(state, M - i))]);
  }
  pick.resize(nt);
  std::sort(pick.begin(), pick.end());
  const Eigen::Index D = refX.cols(), d = fit.coordinates.cols();
  RowMatrixF tx(static_cast<Eigen::Index>(nt), D);
  RowMatrixF ty(static_cast<Eigen::Index>(nt), d);
  for (std::size_t i = 0; i < nt; ++i)
  {
    tx.row(static_cast<Eigen::Index>(i)) = refX.row(pick[i]);
    ty.row(static_cast<Eigen::Index>(i)) = fit.coordinates.row(pick[i]);
  }
  fit.trustworthiness =
    trustworthiness(tx.data(), static_cast<int>(D), ty.data(), static_cast<int>(d), nt, k);
}

// The embedding of the reference rows and (`trust`) its trustworthiness.
Fit fitReference(const RowMatrixF& refX, const ReductionOptions& options, const StageProgress& progress, bool trust)
{
  Fit fit;
  const auto start = Clock::now();
  const int d = options.outputDimension;
  // reduceDimension checked the method: it is in the table.
  Embedding embedding = findReductionMethod(options.method)->fit(refX, options, progress, &fit.pca);
  fit.ms = msSince(start);
  fit.warnings = std::move(embedding.warnings);
  if (!embedding.error.empty())
  {
    fit.error = embedding.error;
    return fit;
  }
  if (!embedding.coordinates.allFinite())
  {
    fit.error = std::string(reductionMethodName(options.method)) +
      ": the embedding has non-finite coordinates (degenerate data); try more neighbours or another method.";
    return fit;
  }
  fit.coordinates = std::move(embedding.coordinates);
  fit.eigenvalues = std::move(embedding.eigenvalues);
  fit.varianceRetained = embedding.varianceRetained;
  if (trust)
  {
    measureTrustworthiness(refX, options, fit);
  }
  fit.referenceRadius = embedding.referenceRadius >= 0.0 ? embedding.referenceRadius : referenceRadius(refX);
  return fit;
}

// Plain bytes for sending a Fit from process 0 to the others.
class ByteWriter
{
public:
  void raw(const void* p, std::size_t n)
  {
    const char* c = static_cast<const char*>(p);
    bytes.insert(bytes.end(), c, c + n);
  }
  template <class T>
  void value(const T& v)
  {
    raw(&v, sizeof v);
  }
  template <class T>
  void values(const T* p, std::size_t n)
  {
    value<std::uint64_t>(n);
    raw(p, n * sizeof(T));
  }
  void text(const std::string& s) { values(s.data(), s.size()); }
  std::vector<char> bytes;
};

class ByteReader
{
public:
  explicit ByteReader(const std::vector<char>& bytes)
    : bytes_(bytes)
  {
  }
  void raw(void* p, std::size_t n)
  {
    if (n > 0)
    {
      std::memcpy(p, bytes_.data() + at_, n);
    }
    at_ += n;
  }
  template <class T>
  T value()
  {
    T v;
    raw(&v, sizeof v);
    return v;
  }
  template <class T>
  std::vector<T> values()
  {
    std::vector<T> v(value<std::uint64_t>());
    raw(v.data(), v.size() * sizeof(T));
    return v;
  }
  std::string text()
  {
    const std::vector<char> c = values<char>();
    return std::string(c.begin(), c.end());
  }

private:
  const std::vector<char>& bytes_;
  std::size_t at_ = 0;
};

std::vector<char> pack(const Fit& fit)
{
  ByteWriter w;
  w.text(fit.error);
  w.value<std::uint64_t>(fit.warnings.size());
  for (const std::string& s : fit.warnings)
  {
    w.text(s);
  }
  w.value<std::int64_t>(fit.coordinates.rows());
  w.value<std::int64_t>(fit.coordinates.cols());
  w.raw(fit.coordinates.data(), static_cast<std::size_t>(fit.coordinates.size()) * sizeof(float));
  w.values(fit.eigenvalues.data(), fit.eigenvalues.size());
  w.value(fit.varianceRetained);
  w.value(fit.trustworthiness);
  w.value(fit.ms);
  w.values(fit.pca.mean.data(), static_cast<std::size_t>(fit.pca.mean.size()));
  w.value<std::int64_t>(fit.pca.axes.rows());
  w.value<std::int64_t>(fit.pca.axes.cols());
  w.raw(fit.pca.axes.data(), static_cast<std::size_t>(fit.pca.axes.size()) * sizeof(double));
  w.value(fit.referenceRadius);
  return std::move(w.bytes);
}

Fit unpack(const std::vector<char>& bytes)
{
  ByteReader r(bytes);
  Fit fit;
  fit.error = r.text();
  fit.warnings.resize(r.value<std::uint64_t>());
  for (std::string& s : fit.warnings)
  {
    s = r.text();
  }
  const std::int64_t rows = r.value<std::int64_t>();
  fit.coordinates.resize(rows, r.value<std::int64_t>());
  r.raw(fit.coordinates.data(), static_cast<std::size_t>(fit.coordinates.size()) * sizeof(float));
  fit.eigenvalues = r.values<double>();
  fit.varianceRetained = r.value<double>();
  fit.trustworthiness = r.value<double>();
  fit.ms = r.value<double>();
  const std::vector<double> mean = r.values<double>();
  fit.pca.mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(mean.size()));
  const std::int64_t axesRows = r.value<std::int64_t>();
  fit.pca.axes.resize(axesRows, r.value<std::int64_t>());
  r.raw(fit.pca.axes.data(), static_cast<std::size_t>(fit.pca.axes.size()) * sizeof(double));
  fit.referenceRadius = r.value<double>();
  return fit;
}

// Process 0 fits and every process gets its answer, so the embedding, spectrum, warnings and
// trustworthiness are the same everywhere (the others would only repeat the work). `trust`
// false: the trustworthiness is left to the caller (serial runs only).
Fit fitOnFirst(const RowMatrixF& refX, const ReductionOptions& options, const Communicator* comm,
  const StageProgress& progress, bool trust)
{
  const bool distributed = isDistributed(comm);
  Fit fit;
  if (!distributed || comm->rank() == 0)
  {
    const std::string failure = runShared(nullptr, [&] { fit = fitReference(refX, options, progress, trust); });
    if (!failure.empty())
    {
      fit = Fit();
      fit.error = failure;
    }
  }
  if (!distributed)
  {
    return fit;
  }
  const std::vector<char> bytes = comm->allGather(comm->rank() == 0 ? pack(fit) : std::vector<char>());
  return comm->rank() == 0 ? fit : unpack(bytes);
}

// ---- The whole: one run of the stages ----------------------------------------------------

// One call of reduce(): its inputs, what the stages have found so far, and its progress.
// Each stage returns an error message (empty when it went well); the options are the same
// on every process, so are the stages' answers.
struct Run
{
  Run(FeatureRows& f, const ReductionOptions& o)
    : features(f)
    , options(o)
    , comm(o.communicator)
    , model(o.model)
  {
  }

  FeatureRows& features;
  const ReductionOptions& options;
  const Communicator* const comm;
  const ReductionModel* const model;
  ReductionResult result;
  ReductionMethod method = ReductionMethod::PCA;
  int d = 0;
  bool projects = false;
  bool graphMethod = false;
  RowLayout rows = RowLayout::plain(0);
  std::size_t N = 0; // voxels of every process
  int cols = 0;
  Device device = Device::CPU;
  // The references: the model's, or fitted on a sample of the rows.
  std::vector<int> used;
  RowMatrixF refX;
  Fit fit;
  std::size_t M = 0;
  // The trustworthiness is measured beside the placement (see reduce()).
  bool trustBesidePlacement = false;

  ReductionResult failed(std::string message)
  {
    result.error = std::move(message);
    result.coordinates.clear();
    return std::move(result);
  }
  void report(const char* stage, double f) const
  {
    if (options.progress)
    {
      options.progress(stage, std::min(1.0, std::max(0.0, f)));
    }
  }
  // Progress of a stage mapped into [lo, hi] of the whole.
  StageProgress within(double lo, double hi) const
  {
    return [this, lo, hi](const char* stage, double f) { report(stage, lo + (hi - lo) * f); };
  }

  std::string checkOptions();
  std::string checkSampleOptions() const;
  std::string countRows(const std::string& inputError);
  std::string takeModel();
  std::string chooseColumns(std::vector<double>& usedMean, bool devicePasses);
  std::string drawSample(const std::vector<double>& usedMean, bool devicePasses);
  std::string fitSample();
  void exportModel() const;
};

// --- Checks of the options (before any row is read) --------------------------------------
std::string Run::checkOptions()
{
  if (model)
  {
    const std::string broken = model->check();
    if (!broken.empty())
    {
      return "The reduction model is not usable: " + broken + ".";
    }
  }
  method = model ? model->method : options.method;
  d = model ? model->outputDimension : options.outputDimension;
  if (d != 2 && d != 3)
  {
    return "OutputDimension must be 2 or 3 (got " + std::to_string(d) + ").";
  }
  const ReductionMethodInfo* const methodInfo = findReductionMethod(method);
  if (!methodInfo)
  {
    return "Unknown reduction method " + std::to_string(static_cast<int>(method)) + ".";
  }
  projects = methodInfo->projects;
  graphMethod = methodInfo->neighbourGraph && !model;
  const std::string sampling = checkSampleOptions();
  if (!sampling.empty())
  {
    return sampling;
  }
  if (options.coordinatesOutput && options.coordinatesHalfOutput)
  {
    return "Give the coordinates one destination: coordinatesOutput (float32) or coordinatesHalfOutput (float16).";
  }
  if (options.modelDistanceOutput && !model)
  {
    return "A model distance (modelDistanceOutput) is measured against a model: set options.model.";
  }
  if (options.timeSteps < 1 || (options.timeSteps > 1 && (!options.fitOnly || options.model)))
  {
    return "Several time steps (timeSteps " + std::to_string(options.timeSteps) +
      ") are fitted together only (fitOnly, no model); each step is placed on its own.";
  }
  return {};
}

// The neighbour graph's and the reference sample's settings (a model needs neither).
std::string Run::checkSampleOptions() const
{
  if (graphMethod && options.numberOfNeighbors < 1)
  {
    return "NumberOfNeighbors must be at least 1 (got " + std::to_string(options.numberOfNeighbors) + ").";
  }
  if (graphMethod && options.numberOfLandmarks < 1)
  {
    return "NumberOfLandmarks must be at least 1 (got " + std::to_string(options.numberOfLandmarks) + ").";
  }
  if (options.referenceSampleSize == 0 && !model)
  {
    return "ReferenceSampleSize must be at least 1.";
  }
  // Said before sampling: the setting, not the data, is what cannot be fitted.
  if (options.referenceSampleSize < static_cast<std::size_t>(d) + 2 && !model)
  {
    return "ReferenceSampleSize (" + std::to_string(options.referenceSampleSize) + ") is too small: a " +
      std::to_string(d) + "D embedding is fitted on at least " + std::to_string(d + 2) +
      " reference points; raise ReferenceSampleSize (or lower OutputDimension).";
  }
  return {};
}

// --- The rows of every process -----------------------------------------------------------
std::string Run::countRows(const std::string& inputError)
{
  std::string error = sharedError(comm, inputError.empty() ? checkRows(features, options) : inputError);
  if (error.empty())
  {
    error = checkAgreement(features, options, comm);
  }
  if (!error.empty())
  {
    return error;
  }
  rows = makeLayout(features, options, comm);
  std::vector<double> voxels{ static_cast<double>(rows.ownedCount()) };
  if (isDistributed(comm))
  {
    comm->sum(voxels);
  }
  N = static_cast<std::size_t>(voxels[0]);
  if (N == 0)
  {
    return "The feature array has no rows (no voxels): nothing to reduce.";
  }
  if (hasGrid(options) &&
    N != GridPiece::whole(ImageGrid{ options.piece.wholeDims }).ownedCount() * static_cast<std::size_t>(options.timeSteps))
  {
    return "The processes own " + std::to_string(N) + " voxels of a volume of " + dimsText(options.piece.wholeDims) +
      ": every voxel must be owned by exactly one process.";
  }
  cols = features.cols();
  if (cols < 2)
  {
    return "The feature array has " + std::to_string(cols) +
      " component(s): nothing to reduce (at least 2 features are needed).";
  }
  return {};
}

// --- The references of a model ---------------------------------------------------------------
std::string Run::takeModel()
{
  if (cols != model->featureColumns)
  {
    return "The reduction model was fitted on " + std::to_string(model->featureColumns) +
      " feature columns; these rows have " + std::to_string(cols) + ".";
  }
  used = model->usedColumns;
  M = model->references;
  const Eigen::Index D = static_cast<Eigen::Index>(used.size());
  refX = Eigen::Map<const RowMatrixF>(model->referenceFeatures.data(), static_cast<Eigen::Index>(M), D);
  fit.coordinates = Eigen::Map<const RowMatrixF>(model->referenceCoordinates.data(), static_cast<Eigen::Index>(M), d);
  fit.pca.mean = Eigen::Map<const Eigen::VectorXd>(model->pcaMean.data(), static_cast<Eigen::Index>(model->pcaMean.size()));
  fit.pca.axes = Eigen::Map<const Eigen::MatrixXd>(model->pcaAxes.data(), projects ? D : 0, projects ? d : 0);
  fit.referenceRadius = model->referenceRadius;
  result.usedColumns = used;
  result.eigenvalues = model->eigenvalues;
  result.varianceRetained = model->varianceRetained;
  result.trustworthiness = model->trustworthiness;
  result.modelApplied = true;
  return {};
}

// --- The columns that vary (statistics over every row) -------------------------------------
// NaN/Inf are an error: they have no place in a distance, and silently dropping voxels
// would leave holes in the output. The message says where the first one is.
std::string Run::chooseColumns(std::vector<double>& usedMean, bool devicePasses)
{
  ColumnStats stats(cols);
  std::string error;
  const std::function<void(double)> statsProgress = [&](double f) { report("Column statistics", 0.03 * f); };
  if (!(devicePasses && deviceColumnStats(features, statsProgress, stats, result.warnings)))
  {
    error = runShared(comm, [&] { stats = localStats(features, rows, statsProgress); });
  }
  if (!error.empty())
  {
    return error;
  }
  combineStats(stats, static_cast<double>(N), comm);
  if (stats.nonFinite > 0)
  {
    const std::int64_t first = static_cast<std::int64_t>(stats.firstBad);
    return "The features contain " + std::to_string(static_cast<std::int64_t>(stats.nonFinite)) +
      " non-finite value(s) (NaN or Inf), the first at voxel " + std::to_string(first / cols) + ", component " +
      std::to_string(first % cols) + "; replace or mask them before reducing.";
  }
  std::string dropped;
  for (int c = 0; c < cols; ++c)
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
    result.warnings.push_back(
      "Constant feature component(s) " + dropped + " (zero variance) carry no information and were left out.");
  }
  if (used.size() < 2)
  {
    return "Only " + std::to_string(used.size()) + " of the " + std::to_string(cols) +
      " feature components vary: nothing to reduce.";
  }
  result.usedColumns = used;
  return {};
}

// --- Reference sample (the same voxels on every process) -----------------------------------
std::string Run::drawSample(const std::vector<double>& usedMean, bool devicePasses)
{
  report("Drawing the reference sample", 0.03);
  const unsigned char* mask = options.sampleMask;
  const std::size_t eligible = sampleableVoxels(rows, mask, N, comm);
  if (mask && eligible == 0)
  {
    result.warnings.push_back("The foreground mask marks no voxel (every voxel is background): the reference "
                              "sample is drawn from all voxels.");
    mask = nullptr;
  }
  const std::size_t Ns = mask ? eligible : N;
  const char* const what = mask ? "foreground voxels" : "voxels";
  result.sampledVoxels = Ns;
  if (options.referenceSampleSize > Ns)
  {
    result.warnings.push_back("ReferenceSampleSize (" + std::to_string(options.referenceSampleSize) +
      ") exceeds the number of " + what + " (" + std::to_string(Ns) + "); the embedding is fitted on all of them.");
  }
  ReferenceSampleOptions so;
  so.size = options.referenceSampleSize;
  so.seed = options.randomSeed;
  so.eligible = mask;
  so.progress = [&](double f) { report("Drawing the reference sample", 0.03 + 0.02 * f); };
  so.onDevice = devicePasses;
  ReferenceSample sample = drawReferenceSample(features, rows, used, usedMean, so, comm);
  result.warnings.insert(result.warnings.end(), sample.warnings.begin(), sample.warnings.end());
  if (!sample.error.empty())
  {
    return "Drawing the reference sample: " + sample.error;
  }
  result.referenceIndices = std::move(sample.indices);
  M = result.referenceIndices.size();
  const std::size_t wanted = std::min(options.referenceSampleSize, Ns);
  if (M < wanted)
  {
    result.warnings.push_back("Only " + std::to_string(M) + " distinct feature vectors were found for a reference sample of " +
      std::to_string(wanted) + " (identical voxels are fitted once).");
  }
  if (graphMethod && static_cast<std::size_t>(options.numberOfNeighbors) >= M)
  {
    return "NumberOfNeighbors (" + std::to_string(options.numberOfNeighbors) +
      ") must be less than the number of distinct reference points (" + std::to_string(M) +
      "); lower it or raise ReferenceSampleSize.";
  }
  if (M < static_cast<std::size_t>(d) + 2)
  {
    return "Only " + std::to_string(M) + " distinct feature vectors: at least " + std::to_string(d + 2) +
      " are needed for a " + std::to_string(d) + "D embedding.";
  }
  refX = Eigen::Map<const RowMatrixF>(sample.vectors.data(), static_cast<Eigen::Index>(M),
    static_cast<Eigen::Index>(used.size()));
  return {};
}

// --- Fit (process 0; its answer is shared) -----------------------------------------------------
std::string Run::fitSample()
{
  report("Fitting the embedding", 0.05);
  fit = fitOnFirst(refX, options, comm, within(0.05, 0.6), !trustBesidePlacement);
  result.fitMs = fit.ms;
  result.warnings.insert(result.warnings.end(), fit.warnings.begin(), fit.warnings.end());
  if (!fit.error.empty())
  {
    return fit.error;
  }
  result.eigenvalues = fit.eigenvalues;
  result.varianceRetained = fit.varianceRetained;
  result.trustworthiness = fit.trustworthiness;
  return {};
}

// --- The fitted model, for the caller to keep ----------------------------------------------------
void Run::exportModel() const
{
  ReductionModel& out = *options.fittedModel;
  out = ReductionModel();
  out.method = method;
  out.outputDimension = d;
  out.featureColumns = cols;
  out.usedColumns = used;
  out.references = M;
  out.referenceFeatures.assign(refX.data(), refX.data() + refX.size());
  out.referenceCoordinates.assign(fit.coordinates.data(), fit.coordinates.data() + fit.coordinates.size());
  if (projects)
  {
    out.pcaMean.assign(fit.pca.mean.data(), fit.pca.mean.data() + fit.pca.mean.size());
    out.pcaAxes.assign(fit.pca.axes.data(), fit.pca.axes.data() + fit.pca.axes.size());
  }
  out.referenceRadius = fit.referenceRadius;
  out.eigenvalues = fit.eigenvalues;
  out.varianceRetained = fit.varianceRetained;
  out.trustworthiness = fit.trustworthiness;
}

// ---- Every row of this process (local) --------------------------------------------------------

// The placement of this process's rows after the fit: where each row's coordinates go
// (float32, float16, the kept box of a split run's piece), and, applying a model, each
// row's distance to it.
class Placement
{
public:
  explicit Placement(Run& run)
    : run_(run)
    , o_(run.options)
    , n_(run.features.rows())
    , du_(static_cast<std::size_t>(run.d))
    , kept_(keptRows(run.options, n_))
    , halves_(run.options.coordinatesHalfOutput)
    , coordinates_(run.options.coordinatesOutput)
    , gatherColumns_(static_cast<int>(run.used.size()) == run.cols ? std::vector<int>{} : run.used)
  {
    if (!coordinates_ && !halves_)
    {
      run.result.coordinates.resize(kept_.rows() * du_);
      coordinates_ = run.result.coordinates.data();
    }
  }

  // Every row placed; an error when a collective check fails.
  std::string placeAll();

private:
  float* floatsFor(std::size_t begin, std::size_t count);
  void written(std::size_t begin, std::size_t count, const float* values);
  void measure(std::size_t begin, std::size_t count, const float* rowsOfChunk, const std::uint32_t* nearest,
    std::size_t stride);
  void keepDistance(std::size_t from, std::size_t to, std::size_t rowsKept, const float* distances);
  std::size_t placeOnDevice(Device& blockDevice);
  void placeBlocks(std::size_t placedRows, Device blockDevice);
  void placeChunk(const float* rowsOfChunk, std::size_t begin, std::size_t count, double lo, double hi,
    Device blockDevice);
  std::string finalChecks() const;

  Run& run_;
  const ReductionOptions& o_;
  const std::size_t n_;
  const std::size_t du_;
  // float16 output: each piece of rows is placed into `scratch_` (one chunk) and rounded
  // into the caller's binary16 array; `coordinates_` stays null.
  // A box of the block as output (a split run's piece): each chunk is placed into
  // `scratch_` and its kept rows copied out, as for float16.
  const KeptRows kept_;
  std::uint16_t* const halves_;
  float* coordinates_;
  const std::vector<int> gatherColumns_;
  std::vector<float> scratch_;
  std::size_t overflow_ = 0;
  // Applying a model: each output row's distance to it (ModelDistance.h) and the rows that
  // are not finite (no statistics pass caught them).
  std::unique_ptr<ExactKnn> nearestIndex_;
  std::vector<float> distanceScratch_;
  std::size_t outOfModel_ = 0, nonFiniteRows_ = 0;
};

// Where rows [begin, begin + count) are to be written as float (count <= the chunk for
// float16 or a box).
float* Placement::floatsFor(std::size_t begin, std::size_t count)
{
  if (!halves_ && kept_.all())
  {
    return coordinates_ + begin * du_;
  }
  scratch_.resize(count * du_);
  return scratch_.data();
}

// The hand-over of rows [begin, begin + count) once written at `values`.
void Placement::written(std::size_t begin, std::size_t count, const float* values)
{
  if (!halves_ && kept_.all())
  {
    return;
  }
  kept_.runs(begin, count, [&](std::size_t from, std::size_t to, std::size_t rowsKept) {
    const float* source = values + (from - begin) * du_;
    if (halves_)
    {
      overflow_ += floatsToHalves(source, rowsKept * du_, halves_ + to * du_);
    }
    else
    {
      std::copy(source, source + rowsKept * du_, coordinates_ + to * du_);
    }
  });
}

// One kept run's distances to the model (distances[0] is row `from`).
void Placement::keepDistance(std::size_t from, std::size_t to, std::size_t rowsKept, const float* distances)
{
  for (std::size_t r = 0; r < rowsKept; ++r)
  {
    const float v = distances[r];
    o_.modelDistanceOutput[to + r] = v;
    outOfModel_ += v > kOutOfModelRatio ? 1 : 0;
  }
}

void Placement::measure(std::size_t begin, std::size_t count, const float* rowsOfChunk, const std::uint32_t* nearest,
  std::size_t stride)
{
  if (!run_.model)
  {
    return;
  }
  const std::size_t cols = static_cast<std::size_t>(run_.cols);
  for (std::size_t r = 0; r < count; ++r)
  {
    const float* row = rowsOfChunk + r * cols;
    for (int c : run_.used)
    {
      if (!std::isfinite(row[c]))
      {
        ++nonFiniteRows_;
        break;
      }
    }
  }
  if (!o_.modelDistanceOutput)
  {
    return;
  }
  if (!nearest && !nearestIndex_)
  {
    nearestIndex_.reset(new ExactKnn(run_.refX.data(), run_.M, static_cast<int>(run_.used.size())));
  }
  distanceScratch_.resize(count);
  modelDistances(run_.refX, nearestIndex_.get(), run_.fit.referenceRadius, rowsOfChunk, count, run_.cols,
    gatherColumns_, nearest, stride, distanceScratch_.data());
  kept_.runs(begin, count, [&](std::size_t from, std::size_t to, std::size_t rowsKept) {
    keepDistance(from, to, rowsKept, distanceScratch_.data() + (from - begin));
  });
}

std::string Placement::placeAll()
{
  const Fit& fit = run_.fit;
  if (run_.projects && o_.device == Device::GPU)
  {
    run_.result.warnings.push_back("The PCA projection (a small matrix product per voxel) runs on the CPU.");
  }
  if (!run_.model && !run_.projects && !isDistributed(run_.comm) && !hasGrid(o_) && run_.M == n_)
  {
    // Every row is a reference point (M distinct indices of [0, rows) in order): its
    // embedding is the fit's, which the placement would return after a kNN search per row.
    if (halves_)
    {
      written(0, n_, fit.coordinates.data());
    }
    else
    {
      std::copy(fit.coordinates.data(), fit.coordinates.data() + fit.coordinates.size(), coordinates_);
    }
  }
  else
  {
    // Rows made on the GPU (the fused path: features per slab on the device) are placed
    // there too; after a GPU failure the CPU places the rows from the first one not done,
    // with one warning.
    Device blockDevice = run_.device;
    const std::size_t placedRows = !run_.projects && run_.device == Device::GPU ? placeOnDevice(blockDevice) : 0;
    placeBlocks(placedRows, blockDevice);
  }
  return finalChecks();
}

// The GPU's placement of the rows it made; returns how many rows it placed, and sets
// `blockDevice` to the CPU where the rest must be placed there.
std::size_t Placement::placeOnDevice(Device& blockDevice)
{
  ReductionResult& result = run_.result;
  DevicePlacement request;
  request.refX = run_.refX.data();
  request.refY = run_.fit.coordinates.data();
  request.M = run_.M;
  request.D = static_cast<int>(run_.used.size());
  request.d = run_.d;
  request.columns = gatherColumns_.empty() ? nullptr : gatherColumns_.data();
  request.distanceMargin = floatDistanceMargin(request.D);
  // The device writes every row of the block: a box as output takes them through a
  // block-sized staging array (the GPU path keeps the block's memory, the CPU's not).
  std::vector<float> stagedFloats;
  std::vector<std::uint16_t> stagedHalves;
  if (!kept_.all())
  {
    (halves_ ? stagedHalves.resize(n_ * du_) : stagedFloats.resize(n_ * du_));
  }
  request.out = kept_.all() ? coordinates_ : (halves_ ? nullptr : stagedFloats.data());
  request.outHalf = kept_.all() ? halves_ : (halves_ ? stagedHalves.data() : nullptr);
  request.progress = [&](double f) { run_.report("Out-of-sample placement (GPU)", 0.6 + 0.35 * f); };
  // Applying a model: the distances to it come from the device with the coordinates.
  std::vector<float> deviceDistances(run_.model && o_.modelDistanceOutput ? n_ : 0);
  request.distance = deviceDistances.empty() ? nullptr : deviceDistances.data();
  request.modelRadius = run_.fit.referenceRadius;
  run_.report("Out-of-sample placement (GPU)", 0.6);
  const DevicePlacementReport placed = run_.features.placeOnDevice(request);
  overflow_ += placed.halfOverflow;
  if (!placed.attempted)
  {
    return 0;
  }
  const std::size_t done = placed.error.empty() ? n_ : std::min(n_, placed.rowsDone);
  if (!kept_.all())
  {
    kept_.runs(0, done, [&](std::size_t from, std::size_t to, std::size_t rowsKept) {
      if (halves_)
      {
        std::copy(stagedHalves.data() + from * du_, stagedHalves.data() + (from + rowsKept) * du_, halves_ + to * du_);
      }
      else
      {
        std::copy(stagedFloats.data() + from * du_, stagedFloats.data() + (from + rowsKept) * du_, coordinates_ + to * du_);
      }
    });
  }
  if (request.distance)
  {
    kept_.runs(0, done, [&](std::size_t from, std::size_t to, std::size_t rowsKept) {
      keepDistance(from, to, rowsKept, deviceDistances.data() + from);
    });
  }
  if (placed.error.empty())
  {
    result.deviceUsed = Device::GPU;
    return n_;
  }
  if (placed.rowsDone >= n_)
  {
    // Every coordinate had come down when the GPU failed.
    result.deviceUsed = Device::GPU;
    result.warnings.push_back("The GPU fused placement failed after " + std::to_string(n_) + " of " +
      std::to_string(n_) + " voxels (" + placed.error + "); nothing was left for the CPU.");
    return n_;
  }
  blockDevice = Device::CPU;
  result.warnings.push_back("The GPU fused placement failed after " + std::to_string(placed.rowsDone) + " of " +
    std::to_string(n_) + " voxels (" + placed.error + "); the rest ran on the CPU.");
  return placed.rowsDone;
}

// Block by block (one block for a matrix in memory; the fused path computes each block's
// features here): progress after each, so an abort stops between blocks.
void Placement::placeBlocks(std::size_t placedRows, Device blockDevice)
{
  FeatureRows& features = run_.features;
  const std::size_t blocks = placedRows == n_ ? 0 : features.blockCount();
  const std::size_t chunkRows =
    halves_ || !kept_.all() ? kHalfPlacementRows : std::numeric_limits<std::size_t>::max();
  const double rowsAll = static_cast<double>(std::max<std::size_t>(1, n_));
  for (std::size_t b = 0; b < blocks; ++b)
  {
    const std::size_t blockBegin = features.blockBegin(b), blockEnd = features.blockBegin(b + 1);
    if (blockEnd <= placedRows)
    {
      continue;
    }
    // A block the GPU placed in part: its remaining rows.
    const std::size_t blockFirst = std::max(blockBegin, placedRows);
    if (blockEnd <= blockFirst)
    {
      continue;
    }
    const float* const blockRows = features.block(b);
    // In chunks for float16 output (the scratch), else the block at once.
    for (std::size_t begin = blockFirst; begin < blockEnd; begin += std::min(chunkRows, blockEnd - begin))
    {
      const std::size_t count = std::min(chunkRows, blockEnd - begin);
      const double lo = 0.6 + 0.35 * static_cast<double>(begin) / rowsAll;
      const double hi = 0.6 + 0.35 * static_cast<double>(begin + count) / rowsAll;
      const float* rowsOfChunk = blockRows + (begin - blockBegin) * static_cast<std::size_t>(run_.cols);
      placeChunk(rowsOfChunk, begin, count, lo, hi, blockDevice);
    }
  }
}

// Rows [begin, begin + count), projected (PCA) or placed by their nearest references.
void Placement::placeChunk(const float* rowsOfChunk, std::size_t begin, std::size_t count, double lo, double hi,
  Device blockDevice)
{
  ReductionResult& result = run_.result;
  run_.report(run_.projects ? "PCA projection" : "Out-of-sample placement", lo);
  float* out = floatsFor(begin, count);
  if (run_.projects)
  {
    projectPCA(run_.fit.pca, rowsOfChunk, count, run_.cols, gatherColumns_, out);
    written(begin, count, out);
    measure(begin, count, rowsOfChunk, nullptr, 0);
    return;
  }
  OutOfSampleOptions oo;
  oo.device = blockDevice;
  oo.progress = run_.within(lo, hi);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(oo.neighbors), run_.M);
  std::vector<std::uint32_t> neighbors(o_.modelDistanceOutput ? count * k : 0);
  const OutOfSampleReport placed = placeOutOfSample(run_.refX, run_.fit.coordinates, rowsOfChunk, count, run_.cols,
    gatherColumns_, out, oo, neighbors.empty() ? nullptr : neighbors.data());
  written(begin, count, out);
  measure(begin, count, rowsOfChunk, neighbors.empty() ? nullptr : neighbors.data(), k);
  result.deviceUsed = placed.deviceUsed;
  for (const std::string& w : placed.warnings)
  {
    if (std::find(result.warnings.begin(), result.warnings.end(), w) == result.warnings.end())
    {
      result.warnings.push_back(w); // once, not once per block
    }
  }
}

// Collective, like the other errors: every process fails together, and all hear the whole
// count.
std::string Placement::finalChecks() const
{
  const Communicator* comm = run_.comm;
  if (halves_)
  {
    std::vector<double> over{ static_cast<double>(overflow_) };
    if (isDistributed(comm))
    {
      comm->sum(over);
    }
    if (over[0] > 0)
    {
      return std::to_string(static_cast<std::int64_t>(over[0])) +
        " reduced coordinate value(s) exceed float16's range (|x| > 65504); use CoordinatePrecision Float32.";
    }
  }
  if (run_.model)
  {
    std::vector<double> counts{ static_cast<double>(nonFiniteRows_), static_cast<double>(outOfModel_) };
    if (isDistributed(comm))
    {
      comm->sum(counts);
    }
    if (counts[0] > 0)
    {
      return "The features contain non-finite values (NaN or Inf) in " +
        std::to_string(static_cast<std::int64_t>(counts[0])) + " voxel(s); replace or mask them before reducing.";
    }
    run_.result.outOfModelVoxels = static_cast<std::size_t>(counts[1]);
  }
  return {};
}

// Joins a helper thread however the scope ends (an exception must not meet a running thread).
struct JoinOnExit
{
  std::thread& thread;
  ~JoinOnExit()
  {
    if (thread.joinable())
    {
      thread.join();
    }
  }
};

// `inputError`: what the caller found wrong with its rows (shared like the other checks).
ReductionResult reduce(FeatureRows& features, const ReductionOptions& options, const std::string& inputError)
{
  const auto start = Clock::now();
  Run run(features, options);
  std::string error = run.checkOptions();
  if (!error.empty())
  {
    return run.failed(error);
  }
  run.result.outputDimension = run.d;
  run.report("Checking features", 0.0);
  error = run.countRows(inputError);
  if (!error.empty())
  {
    return run.failed(error);
  }
  // The coordinates array of the result (85 MB for 7.1 M voxels in 3D) is zero-filled by
  // std::vector page by page on one thread, after the fit and before the placement: it is
  // made on a thread of its own while the sample is drawn and the embedding fitted, and
  // handed to the placement (which would make the same array).
  std::vector<float> preparedCoordinates;
  std::thread preparing;
  const JoinOnExit joinPreparing{ preparing };
  if (!options.coordinatesOutput && !options.coordinatesHalfOutput && !options.fitOnly)
  {
    const std::size_t values = keptRows(options, features.rows()).rows() * static_cast<std::size_t>(run.d);
    preparing = std::thread([&preparedCoordinates, values] {
      try
      {
        preparedCoordinates.resize(values);
      }
      catch (const std::bad_alloc&)
      {
        // The placement allocates it again and reports the failure.
      }
    });
  }
  std::string deviceWarning;
  run.device = resolveDevice(options.device, &deviceWarning);
  if (!deviceWarning.empty())
  {
    run.result.warnings.push_back(deviceWarning);
  }
  if (run.model)
  {
    error = run.takeModel();
  }
  else
  {
    // Where the rows are computed on the GPU and this process owns them all, the passes over
    // every row (the column statistics, the sample's strata) run there too.
    const bool devicePasses = run.device == Device::GPU && !isDistributed(run.comm) &&
      run.rows.ownedCount() == features.rows();
    // On the GPU the host mostly waits for the device while it places the rows: the
    // trustworthiness (which the placement does not need) is measured then, on a thread of
    // its own, instead of between the fit and the placement.
    run.trustBesidePlacement = run.device == Device::GPU && !isDistributed(run.comm) && !options.fitOnly;
    std::vector<double> usedMean;
    error = run.chooseColumns(usedMean, devicePasses);
    error = error.empty() ? run.drawSample(usedMean, devicePasses) : error;
    error = error.empty() ? run.fitSample() : error;
  }
  if (!error.empty())
  {
    return run.failed(error);
  }
  run.result.deviceUsed = Device::CPU; // the placement says where it really ran
  if (options.fittedModel && !run.model && !run.trustBesidePlacement)
  {
    run.exportModel();
  }
  if (options.fitOnly && !run.model)
  {
    run.result.totalMs = msSince(start);
    run.report("Done", 1.0);
    return std::move(run.result);
  }
  std::string trustError;
  const std::size_t fitWarnings = run.fit.warnings.size();
  std::thread trust;
  const JoinOnExit joinTrust{ trust };
  if (run.trustBesidePlacement)
  {
    // Reads refX and the fit's coordinates, which the placement only reads too; writes the
    // fit's trustworthiness and warnings, which the placement does not touch.
    trust = std::thread([&run, &options, &trustError] {
      trustError = runShared(nullptr, [&] { measureTrustworthiness(run.refX, options, run.fit); });
    });
  }
  if (preparing.joinable())
  {
    preparing.join();
    run.result.coordinates.swap(preparedCoordinates);
  }
  const auto placeStart = Clock::now();
  error = Placement(run).placeAll();
  if (trust.joinable())
  {
    trust.join();
    run.result.trustworthiness = run.fit.trustworthiness;
    run.result.warnings.insert(
      run.result.warnings.end(), run.fit.warnings.begin() + static_cast<std::ptrdiff_t>(fitWarnings), run.fit.warnings.end());
    if (options.fittedModel)
    {
      run.exportModel();
    }
    error = error.empty() ? trustError : error;
  }
  if (!error.empty())
  {
    return run.failed(error);
  }
  run.result.placeMs = msSince(placeStart);
  run.result.totalMs = msSince(start);
  run.report("Done", 1.0);
  return std::move(run.result);
}

// reduce() with its failures (memory, exceptions) as errors.
ReductionResult reduceGuarded(FeatureRows& features, const ReductionOptions& options, const std::string& inputError)
{
  try
  {
    return reduce(features, options, inputError);
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
} // namespace

ReductionResult reduceDimension(const FeatureMatrix& features, const ReductionOptions& options)
{
  MatrixRows rows(features.data, features.rows, features.cols);
  return reduceGuarded(rows, options,
    features.rows > 0 && features.data == nullptr
      ? "The feature array has " + std::to_string(features.rows) + " rows but no data."
      : std::string());
}

ReductionResult reduceDimension(FeatureRows& features, const ReductionOptions& options)
{
  return reduceGuarded(features, options, {});
}

} // namespace mcv
