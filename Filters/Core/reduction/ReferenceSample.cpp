#include "ReferenceSample.h"

#ifdef MCV_HAS_CUDA
#include "cuda/SampleKeysCuda.h"
#endif
#include "HugePageBuffer.h"
#include "SeededRandom.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <unordered_map>

namespace mcv
{

namespace
{
constexpr std::uint64_t kAllKeys = std::numeric_limits<std::uint64_t>::max(); // a limit that keeps every key
constexpr std::uint8_t kNotOwned = 0xFF;    // stratum of a row this process does not own
constexpr std::size_t kPlainRun = 4096;     // rows per run of a plain layout
constexpr double kEdgeSubsample = 65536.0;  // voxels the strata edges are measured on
// The most rows whose used features the sampler keeps (usedVectors): 1 M rows of 24 floats
// are 96 MB; the brain's draw keeps ~10^5. Beyond it, rows are gathered again when asked for.
constexpr std::size_t kKeptRows = std::size_t(1) << 20;

// The key limit below which a fraction f of uniform 64-bit keys falls.
std::uint64_t keyLimit(double f)
{
  if (!(f < 1.0))
  {
    return kAllKeys;
  }
  return static_cast<std::uint64_t>(std::ldexp(std::max(f, 0.0), 64));
}

float featureValue(float v)
{
  return v == 0.f ? 0.f : v; // -0 and +0 are one vector
}

// Distinct vectors of D floats among the rows of a contiguous buffer.
class VectorSet
{
public:
  VectorSet(const float* base, std::size_t D)
    : base_(base)
    , D_(D)
  {
  }

  // True (and remembered) when row i's vector was not seen before.
  bool insert(std::size_t i)
  {
    const std::uint64_t h = hash(i);
    const auto range = seen_.equal_range(h);
    for (auto it = range.first; it != range.second; ++it)
    {
      if (equal(i, it->second))
      {
        return false;
      }
    }
    seen_.emplace(h, i);
    return true;
  }

private:
  const float* at(std::size_t i) const { return base_ + i * D_; }
  std::uint64_t hash(std::size_t i) const
  {
    std::uint64_t h = 0x84222325CBF29CE4ull;
    for (std::size_t c = 0; c < D_; ++c)
    {
      const float v = featureValue(at(i)[c]);
      std::uint32_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      h = (h ^ bits) * 0x100000001B3ull;
      h ^= h >> 29;
    }
    return h;
  }
  bool equal(std::size_t a, std::size_t b) const
  {
    for (std::size_t c = 0; c < D_; ++c)
    {
      if (featureValue(at(a)[c]) != featureValue(at(b)[c]))
      {
        return false;
      }
    }
    return true;
  }

  const float* base_;
  std::size_t D_;
  std::unordered_multimap<std::uint64_t, std::size_t> seen_;
};

// What a process sends for one candidate voxel, followed by its D used features.
struct CandidateHeader
{
  std::int64_t global;
  std::uint64_t key;
  std::int32_t stratum;
  std::int32_t unused;
};

// A local voxel found below a list's key limit.
struct Entry
{
  std::uint64_t key;
  std::int64_t global;
  std::size_t row;
};

// One list a process proposes candidates from: its owned voxels (all of them, or those of
// one stratum) as distinct vectors in key order. Collected lazily: the voxels with
// key <= limit, so `reps` is exact up to the limit.
struct LocalList
{
  int stratum = -1;        // -1: every voxel
  std::size_t voxels = 0;  // owned voxels in the list
  double fraction = 0.0;   // of the key range collected
  std::uint64_t limit = 0;
  bool collected = false;
  std::vector<Entry> reps; // the voxel with the smallest key of each distinct vector
  bool complete() const { return collected && limit == kAllKeys; }
};

// A candidate after the merge, on every process.
struct Candidate
{
  std::uint64_t key;
  std::int64_t global;
  int stratum;
  std::size_t vector; // row in the merged vector buffer
};

// True when row may be drawn: `eligible` null (every row) or non-zero at the row.
inline bool isEligible(const unsigned char* eligible, std::size_t row)
{
  return eligible == nullptr || eligible[row] != 0;
}

// Calls visit(row, global) for every owned eligible row, OpenMP over runs.
template <class Visit>
void forOwned(const RowLayout& rows, const unsigned char* eligible, const Visit& visit)
{
  const long long runs = static_cast<long long>(rows.runCount());
#pragma omp parallel for schedule(static)
  for (long long r = 0; r < runs; ++r)
  {
    const RowLayout::Run run = rows.run(static_cast<std::size_t>(r));
    for (std::size_t t = 0; t < run.count; ++t)
    {
      if (isEligible(eligible, run.row + t))
      {
        visit(run.row + t, run.global + static_cast<std::int64_t>(t));
      }
    }
  }
}

// forOwned for the rows of [begin, end) alone (a block of a FeatureRows).
template <class Visit>
void forOwnedIn(const RowLayout& rows, const unsigned char* eligible, std::size_t begin, std::size_t end,
  const Visit& visit)
{
  const std::pair<std::size_t, std::size_t> within = rows.runsWithin(begin, end);
  const long long first = static_cast<long long>(within.first), last = static_cast<long long>(within.second);
#pragma omp parallel for schedule(static)
  for (long long r = first; r < last; ++r)
  {
    const RowLayout::Run run = rows.run(static_cast<std::size_t>(r));
    const std::size_t from = std::max(run.row, begin), to = std::min(run.row + run.count, end);
    for (std::size_t row = from; row < to; ++row)
    {
      if (isEligible(eligible, row))
      {
        visit(row, run.global + static_cast<std::int64_t>(row - run.row));
      }
    }
  }
}

// Calls visit(row, global, found) for every owned eligible row, OpenMP over runs, and
// returns what the visits appended to `found`, in no particular order (callers sort by key).
template <class T, class Visit>
std::vector<T> collectOwned(const RowLayout& rows, const unsigned char* eligible, const Visit& visit)
{
  std::vector<T> all;
  const long long runs = static_cast<long long>(rows.runCount());
#pragma omp parallel
  {
    std::vector<T> found;
#pragma omp for schedule(static) nowait
    for (long long r = 0; r < runs; ++r)
    {
      const RowLayout::Run run = rows.run(static_cast<std::size_t>(r));
      for (std::size_t t = 0; t < run.count; ++t)
      {
        if (isEligible(eligible, run.row + t))
        {
          visit(run.row + t, run.global + static_cast<std::int64_t>(t), found);
        }
      }
    }
#pragma omp critical(mcvCollectOwned)
    all.insert(all.end(), found.begin(), found.end());
  }
  return all;
}

// Draws the sample of ReferenceSample.h on one process of `comm` (null: serial).
class Sampler
{
public:
  Sampler(FeatureRows& source, const RowLayout& rows, const std::vector<int>& columns,
    const std::vector<double>& center, const ReferenceSampleOptions& options, const Communicator* comm)
    : source_(source)
    , dim_(source.cols())
    , rows_(rows)
    , columns_(columns)
    , center_(center)
    , options_(options)
    , comm_(isDistributed(comm) ? comm : nullptr)
    , S_(std::max(1, std::min(options.strata, 254)))
  {
    if (columns_.empty())
    {
      columns_.resize(static_cast<std::size_t>(dim_));
      std::iota(columns_.begin(), columns_.end(), 0);
    }
    D_ = columns_.size();
    const double fraction = std::min(1.0, std::max(0.0, options.stratifiedFraction));
    share_ = static_cast<std::size_t>(std::llround(static_cast<double>(options.size) * fraction)) /
      static_cast<std::size_t>(S_);
  }

  ReferenceSample draw();
  const std::vector<std::string>& warnings() const { return warnings_; }

private:
  float norm(const float* x, bool fullRow) const;
  std::vector<float> usedVectors(const std::vector<std::size_t>& rows);
  std::vector<float> edgeSubsample(double total);
  bool deviceKeyScan(std::uint64_t limit, std::vector<std::size_t>& rows);
  std::vector<float> strataEdges(std::vector<float> norms) const;
  std::vector<double> assignStrata(const std::vector<float>& edges);
  std::vector<std::size_t> firstWants(const std::vector<double>& mine, const std::vector<double>& all) const;
  void fill(const std::vector<std::size_t>& want);
  void collect(const std::vector<std::size_t>& which);
  std::vector<Entry> distinctInKeyOrder(std::vector<Entry> found);
  ReferenceSample everyDistinctVector();
  std::vector<char> propose(const std::vector<std::size_t>& want);
  bool decide(const std::vector<char>& all, std::vector<bool>& more, ReferenceSample& out) const;

  FeatureRows& source_;
  int dim_;
  const RowLayout& rows_;
  std::vector<int> columns_;
  const std::vector<double>& center_;
  ReferenceSampleOptions options_;
  const Communicator* comm_;
  int S_;
  std::size_t D_ = 0;
  std::size_t share_ = 0;             // sample per stratum
  // Per row; kNotOwned for rows of other processes. Not a std::vector, whose resize would
  // zero it on one thread: one byte per voxel of a giga-voxel volume is a gigabyte, whose
  // pages the threads that fill it (OpenMP, or the GPU pass's copies) touch first, in huge
  // pages where the system allows (a quarter of a million 4 KB page faults otherwise).
  std::unique_ptr<HugePageBuffer> strataStorage_;
  std::uint8_t* stratum_ = nullptr;
  std::vector<LocalList> lists_;      // 0: every voxel; 1 + s: stratum s
  // The used features of rows gathered so far (usedVectors): row -> its place in kept_.
  std::unordered_map<std::size_t, std::size_t> keptAt_;
  std::vector<float> kept_;
  std::vector<std::string> warnings_;
  bool deviceKeysFailed_ = false;
};

// The norm of the used, centred features: of a row of dim_ features, or of D_ used ones.
float Sampler::norm(const float* x, bool fullRow) const
{
  double s = 0;
  for (std::size_t k = 0; k < D_; ++k)
  {
    const double v = x[fullRow ? static_cast<std::size_t>(columns_[k]) : k] - (center_.empty() ? 0.0 : center_[k]);
    s += v * v;
  }
  return static_cast<float>(std::sqrt(s));
}

// The used features of `rows` (rows.size() x D_). Rows not seen before are gathered from the
// source in one call (for the fused path that computes the features of just these voxels);
// rows seen before come from the kept copies: the lists are the voxels below growing key
// limits, so each round, the edge subsample and the proposal look at many of the same rows
// (the brain's draw gathered 150 602 voxels in 13 calls before the copies were kept). A
// voxel's features do not depend on what it is gathered with, so the vectors are the same.
std::vector<float> Sampler::usedVectors(const std::vector<std::size_t>& rows)
{
  std::vector<float> used(rows.size() * D_);
  std::vector<std::size_t> missing, missingAt; // rows to gather, and their places in `rows`
  for (std::size_t i = 0; i < rows.size(); ++i)
  {
    const auto kept = keptAt_.find(rows[i]);
    if (kept != keptAt_.end())
    {
      std::copy_n(kept_.begin() + static_cast<std::ptrdiff_t>(kept->second * D_), D_, used.begin() + static_cast<std::ptrdiff_t>(i * D_));
    }
    else
    {
      missing.push_back(rows[i]);
      missingAt.push_back(i);
    }
  }
  if (missing.empty())
  {
    return used;
  }
  std::vector<float> full(missing.size() * static_cast<std::size_t>(dim_));
  source_.gather(missing.data(), missing.size(), full.data());
  for (std::size_t j = 0; j < missing.size(); ++j)
  {
    float* const to = used.data() + missingAt[j] * D_;
    for (std::size_t k = 0; k < D_; ++k)
    {
      to[k] = full[j * static_cast<std::size_t>(dim_) + static_cast<std::size_t>(columns_[k])];
    }
    if (keptAt_.size() < kKeptRows && keptAt_.emplace(missing[j], keptAt_.size()).second)
    {
      kept_.insert(kept_.end(), to, to + D_);
    }
  }
  return used;
}

// The norms of the voxels whose key is below a limit (about kEdgeSubsample voxels of all):
// chosen by the keys alone, so every split measures the strata edges on the same voxels;
// small enough to gather on every process.
std::vector<float> Sampler::edgeSubsample(double total)
{
  const std::uint64_t limit = keyLimit(kEdgeSubsample / total);
  std::vector<std::size_t> picked;
  if (!deviceKeyScan(limit, picked))
  {
    picked = collectOwned<std::size_t>(rows_, options_.eligible, [&](std::size_t row, std::int64_t g, std::vector<std::size_t>& found) {
      if (sampleKey(options_.seed, g) <= limit)
      {
        found.push_back(row);
      }
    });
  }
  const std::vector<float> vectors = usedVectors(picked);
  std::vector<float> norms(picked.size());
  for (std::size_t i = 0; i < picked.size(); ++i)
  {
    norms[i] = norm(vectors.data() + i * D_, false);
  }
  return norms;
}

// The owned eligible rows whose key is at most `limit`, ascending, from the GPU's scan of every
// key (cuda/SampleKeysCuda.h) where the options ask for the device and this process owns
// every row (so row r's global index is the first's plus r); false when the caller scans on
// the CPU (no device, or it failed: said once in the warnings).
bool Sampler::deviceKeyScan(std::uint64_t limit, std::vector<std::size_t>& rows)
{
#ifdef MCV_HAS_CUDA
  if (!options_.onDevice || comm_ || deviceKeysFailed_ || rows_.size() == 0 || rows_.ownedCount() != rows_.size())
  {
    return false;
  }
  std::string error;
  if (!cuda::rowsWithKeyAtMost(options_.seed, rows_.run(0).global, rows_.size(), limit, &rows, &error))
  {
    warnings_.push_back("The GPU key scan of the reference sample failed (" + error + "); it ran on the CPU.");
    deviceKeysFailed_ = true;
    return false;
  }
  if (options_.eligible)
  {
    rows.erase(std::remove_if(rows.begin(), rows.end(), [&](std::size_t r) { return !isEligible(options_.eligible, r); }),
      rows.end());
  }
  return true;
#else
  (void)limit;
  (void)rows;
  return false;
#endif
}

// Stratum edges at the quantiles 1/2, 3/4, 7/8, ... of the subsample's norms.
std::vector<float> Sampler::strataEdges(std::vector<float> norms) const
{
  std::sort(norms.begin(), norms.end());
  std::vector<float> edges;
  const std::size_t n = norms.size();
  for (int s = 1; s < S_ && n > 0; ++s)
  {
    const double q = 1.0 - std::ldexp(1.0, -s);
    edges.push_back(norms[std::min(n - 1, static_cast<std::size_t>(q * static_cast<double>(n)))]);
  }
  return edges;
}

// Every owned row's stratum; returns this process's voxels per list.
std::vector<double> Sampler::assignStrata(const std::vector<float>& edges)
{
  const long long n = static_cast<long long>(rows_.size());
  strataStorage_.reset(new HugePageBuffer((rows_.size() + sizeof(double) - 1) / sizeof(double)));
  stratum_ = reinterpret_cast<std::uint8_t*>(strataStorage_->data()); // bytes of its storage
  const auto notOwned = [&] {
#pragma omp parallel for schedule(static)
    for (long long r = 0; r < n; ++r)
    {
      stratum_[static_cast<std::size_t>(r)] = kNotOwned;
    }
  };
  bool onDevice = false;
  if (options_.onDevice && !comm_)
  {
    DeviceStrata request;
    request.columns = columns_;
    request.center = center_;
    request.edges = edges;
    request.eligible = options_.eligible;
    request.notEligible = kNotOwned;
    request.stratum = stratum_; // every row written (notEligible where not eligible)
    request.progress = options_.progress;
    const DevicePassReport device = source_.strataOnDevice(request);
    onDevice = device.attempted && device.error.empty();
    if (device.attempted && !onDevice)
    {
      warnings_.push_back("The GPU strata of the reference sample failed (" + device.error + "); they ran on the CPU.");
    }
  }
  if (!onDevice)
  {
    notOwned();
  }
  // Block by block: the fused path computes each block's features once for this pass.
  for (std::size_t b = 0; b < (onDevice ? 0 : source_.blockCount()); ++b)
  {
    if (options_.progress && source_.blockCount() > 1)
    {
      options_.progress(static_cast<double>(b) / static_cast<double>(source_.blockCount()));
    }
    const std::size_t begin = source_.blockBegin(b), end = source_.blockBegin(b + 1);
    const float* block = source_.block(b);
    forOwnedIn(rows_, options_.eligible, begin, end, [&](std::size_t row, std::int64_t) {
      const float* x = block + (row - begin) * static_cast<std::size_t>(dim_);
      stratum_[row] = static_cast<std::uint8_t>(std::upper_bound(edges.begin(), edges.end(), norm(x, true)) - edges.begin());
    });
  }
  // Voxels per stratum (a giga-voxel volume: over threads, each counting a part).
  std::vector<std::size_t> count(static_cast<std::size_t>(S_) + 1, 0);
#pragma omp parallel
  {
    std::vector<std::size_t> mine(count.size(), 0);
#pragma omp for schedule(static) nowait
    for (long long r = 0; r < n; ++r)
    {
      const std::uint8_t s = stratum_[static_cast<std::size_t>(r)];
      if (s != kNotOwned)
      {
        ++mine[0];
        ++mine[1 + s];
      }
    }
#pragma omp critical(mcvStrataCount)
    for (std::size_t i = 0; i < count.size(); ++i)
    {
      count[i] += mine[i];
    }
  }
  lists_.assign(count.size(), LocalList{});
  std::vector<double> voxels(count.size());
  for (std::size_t i = 0; i < count.size(); ++i)
  {
    lists_[i].stratum = static_cast<int>(i) - 1;
    lists_[i].voxels = count[i];
    voxels[i] = static_cast<double>(count[i]);
  }
  return voxels;
}

// First guess of how many candidates this process proposes per list: its part of the list's
// voxels times the list's quota, with a margin. Duplicates or chance may leave the merged
// lists short; the next round asks for twice as many.
std::vector<std::size_t> Sampler::firstWants(const std::vector<double>& mine, const std::vector<double>& all) const
{
  std::vector<std::size_t> want(lists_.size(), 0);
  for (std::size_t i = 0; i < want.size(); ++i)
  {
    const std::size_t quota = i == 0 ? options_.size : share_;
    if (quota > 0)
    {
      want[i] = static_cast<std::size_t>(
                  std::ceil(1.25 * static_cast<double>(quota) * mine[i] / std::max(1.0, all[i]))) + 8;
    }
  }
  return want;
}

// Collects until every list holds `want` distinct vectors or all of its voxels.
void Sampler::fill(const std::vector<std::size_t>& want)
{
  for (;;)
  {
    std::vector<std::size_t> grow;
    for (std::size_t i = 0; i < lists_.size(); ++i)
    {
      LocalList& l = lists_[i];
      if (want[i] == 0 || l.complete() || (l.collected && l.reps.size() >= want[i]))
      {
        continue;
      }
      // First a key range expected to hold 1.5 x want voxels; then wider by what the
      // duplicates took (at least twice as wide, so this ends).
      const double w = 1.5 * static_cast<double>(want[i]);
      l.fraction = l.collected
        ? l.fraction * std::max(2.0, w / static_cast<double>(std::max<std::size_t>(1, l.reps.size())))
        : w / static_cast<double>(l.voxels); // no voxels: +inf, i.e. all keys
      l.limit = keyLimit(l.fraction);
      grow.push_back(i);
    }
    if (grow.empty())
    {
      return;
    }
    collect(grow);
  }
}

// One pass over the owned rows collects the voxels below the limits of the lists `which`.
void Sampler::collect(const std::vector<std::size_t>& which)
{
  struct Found
  {
    std::size_t list;
    Entry entry;
  };
  // Most rows are above every limit: one comparison settles them.
  std::uint64_t highest = 0;
  for (std::size_t i : which)
  {
    highest = std::max(highest, lists_[i].limit);
  }
  const auto visit = [&](std::size_t row, std::int64_t g, std::vector<Found>& out) {
    const std::uint64_t key = sampleKey(options_.seed, g);
    if (key > highest)
    {
      return;
    }
    for (std::size_t w = 0; w < which.size(); ++w)
    {
      const LocalList& l = lists_[which[w]];
      if (key <= l.limit && (l.stratum < 0 || l.stratum == stratum_[row]))
      {
        out.push_back({ w, { key, g, row } });
      }
    }
  };
  std::vector<Found> found;
  std::vector<std::size_t> candidates;
  if (deviceKeyScan(highest, candidates))
  {
    // The GPU found the rows below the highest limit; the lists take theirs from them.
    const std::int64_t first = rows_.run(0).global;
    for (std::size_t row : candidates)
    {
      visit(row, first + static_cast<std::int64_t>(row), found);
    }
  }
  else
  {
    found = collectOwned<Found>(rows_, options_.eligible, visit);
  }
  std::vector<std::vector<Entry>> perList(which.size());
  for (const Found& f : found)
  {
    perList[f.list].push_back(f.entry);
  }
  for (std::size_t w = 0; w < which.size(); ++w)
  {
    lists_[which[w]].reps = distinctInKeyOrder(std::move(perList[w]));
    lists_[which[w]].collected = true;
  }
}

std::vector<Entry> Sampler::distinctInKeyOrder(std::vector<Entry> found)
{
  std::sort(found.begin(), found.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
  std::vector<std::size_t> rows(found.size());
  std::transform(found.begin(), found.end(), rows.begin(), [](const Entry& e) { return e.row; });
  const std::vector<float> vectors = usedVectors(rows);
  VectorSet distinct(vectors.data(), D_);
  std::vector<Entry> reps;
  for (std::size_t i = 0; i < found.size(); ++i)
  {
    if (distinct.insert(i))
    {
      reps.push_back(found[i]);
    }
  }
  return reps;
}

// Every distinct vector, each by its lowest-keyed voxel (as the stratified draw takes it when
// it is asked for more than there are), in index order. On one process only.
ReferenceSample Sampler::everyDistinctVector()
{
  std::vector<Entry> reps = distinctInKeyOrder(collectOwned<Entry>(rows_, options_.eligible,
    [&](std::size_t row, std::int64_t g, std::vector<Entry>& out) { out.push_back({ sampleKey(options_.seed, g), g, row }); }));
  std::sort(reps.begin(), reps.end(), [](const Entry& a, const Entry& b) { return a.global < b.global; });
  ReferenceSample out;
  out.indices.resize(reps.size());
  std::vector<std::size_t> rows(reps.size());
  for (std::size_t i = 0; i < reps.size(); ++i)
  {
    out.indices[i] = reps[i].global;
    rows[i] = reps[i].row;
  }
  out.vectors = usedVectors(rows);
  return out;
}

// This process's candidates: per list its first `want` distinct vectors, and a bound: every
// vector of the list it did not propose has a larger key (kAllKeys: none is left). Bytes:
// the bounds (one per list), the candidate count, the candidates (header, then features).
std::vector<char> Sampler::propose(const std::vector<std::size_t>& want)
{
  std::vector<std::uint64_t> bounds(lists_.size(), kAllKeys);
  std::vector<Entry> chosen;
  for (std::size_t i = 0; i < lists_.size(); ++i)
  {
    const LocalList& l = lists_[i];
    const std::size_t k = std::min(want[i], l.reps.size());
    if (want[i] > 0 && !(l.complete() && l.reps.size() <= want[i]))
    {
      bounds[i] = l.reps[k - 1].key; // fill() left at least `want` of them
    }
    chosen.insert(chosen.end(), l.reps.begin(), l.reps.begin() + static_cast<std::ptrdiff_t>(k));
  }
  // A voxel may come in the list of all voxels and in its stratum's: send it once.
  std::sort(chosen.begin(), chosen.end(), [](const Entry& a, const Entry& b) { return a.global < b.global; });
  chosen.erase(std::unique(chosen.begin(), chosen.end(), [](const Entry& a, const Entry& b) { return a.global == b.global; }),
    chosen.end());

  const std::uint64_t count = chosen.size();
  const std::size_t recordBytes = sizeof(CandidateHeader) + D_ * sizeof(float);
  std::vector<char> bytes(bounds.size() * sizeof(std::uint64_t) + sizeof count + chosen.size() * recordBytes);
  char* at = bytes.data();
  std::memcpy(at, bounds.data(), bounds.size() * sizeof(std::uint64_t));
  at += bounds.size() * sizeof(std::uint64_t);
  std::memcpy(at, &count, sizeof count);
  at += sizeof count;
  std::vector<std::size_t> rows(chosen.size());
  std::transform(chosen.begin(), chosen.end(), rows.begin(), [](const Entry& e) { return e.row; });
  const std::vector<float> features = usedVectors(rows);
  for (std::size_t i = 0; i < chosen.size(); ++i)
  {
    const Entry& e = chosen[i];
    const CandidateHeader h{ e.global, e.key, stratum_[e.row], 0 };
    std::memcpy(at, &h, sizeof h);
    std::memcpy(at + sizeof h, features.data() + i * D_, D_ * sizeof(float));
    at += recordBytes;
  }
  return bytes;
}

// Merges every process's candidates (the same bytes on every process, hence the same
// answer) and applies the sampling rule on the part of each merged list that is exact: the
// keys up to the smallest bound of the processes. False, with `more` naming the short lists,
// when that part cannot decide yet.
bool Sampler::decide(const std::vector<char>& all, std::vector<bool>& more, ReferenceSample& out) const
{
  const std::size_t L = lists_.size();
  const std::size_t recordBytes = sizeof(CandidateHeader) + D_ * sizeof(float);
  std::vector<std::uint64_t> bound(L, kAllKeys);
  std::vector<CandidateHeader> headers;
  std::vector<const char*> features;
  for (const char* at = all.data(); at < all.data() + all.size();)
  {
    for (std::size_t i = 0; i < L; ++i, at += sizeof(std::uint64_t))
    {
      std::uint64_t b;
      std::memcpy(&b, at, sizeof b);
      bound[i] = std::min(bound[i], b);
    }
    std::uint64_t count;
    std::memcpy(&count, at, sizeof count);
    at += sizeof count;
    for (std::uint64_t c = 0; c < count; ++c, at += recordBytes)
    {
      CandidateHeader h;
      std::memcpy(&h, at, sizeof h);
      headers.push_back(h);
      features.push_back(at + sizeof h);
    }
  }

  // Key order, then one voxel per distinct vector: the first seen is the lowest-keyed.
  std::vector<std::size_t> order(headers.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return headers[a].key < headers[b].key; });
  std::vector<float> vectors(order.size() * D_);
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    std::memcpy(vectors.data() + i * D_, features[order[i]], D_ * sizeof(float));
  }
  VectorSet distinct(vectors.data(), D_);
  std::vector<Candidate> list;
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    if (distinct.insert(i))
    {
      const CandidateHeader& h = headers[order[i]];
      list.push_back({ h.key, h.global, h.stratum, i });
    }
  }

  // Per stratum, its `share` lowest-keyed distinct vectors.
  more.assign(L, false);
  std::vector<char> taken(list.size(), 0);
  std::size_t total = 0;
  for (int s = 0; s < S_; ++s)
  {
    std::size_t got = 0;
    for (std::size_t i = 0; i < list.size() && got < share_ && list[i].key <= bound[1 + s]; ++i)
    {
      if (list[i].stratum == s)
      {
        taken[i] = 1;
        ++got;
      }
    }
    more[1 + s] = got < share_ && bound[1 + s] != kAllKeys;
    total += got;
  }
  // The uniform rest walks the lowest-keyed vectors of all: it stays within the exact part
  // when that holds `size` vectors (at most `total` of them are taken already).
  const std::size_t exact = static_cast<std::size_t>(
    std::upper_bound(list.begin(), list.end(), bound[0], [](std::uint64_t b, const Candidate& c) { return b < c.key; }) -
    list.begin());
  more[0] = exact < options_.size && bound[0] != kAllKeys;
  if (std::find(more.begin(), more.end(), true) != more.end())
  {
    return false;
  }
  for (std::size_t i = 0; i < list.size() && total < options_.size; ++i)
  {
    if (!taken[i])
    {
      taken[i] = 1;
      ++total;
    }
  }

  std::vector<const Candidate*> chosen;
  for (std::size_t i = 0; i < list.size(); ++i)
  {
    if (taken[i])
    {
      chosen.push_back(&list[i]);
    }
  }
  std::sort(chosen.begin(), chosen.end(), [](const Candidate* a, const Candidate* b) { return a->global < b->global; });
  out.indices.clear();
  out.vectors.resize(chosen.size() * D_);
  for (std::size_t i = 0; i < chosen.size(); ++i)
  {
    out.indices.push_back(chosen[i]->global);
    std::memcpy(out.vectors.data() + i * D_, vectors.data() + chosen[i]->vector * D_, D_ * sizeof(float));
  }
  return true;
}

ReferenceSample Sampler::draw()
{
  ReferenceSample out;
  // Eligible voxels of all processes: the edge subsample and the first guesses depend on it.
  std::vector<double> total{ static_cast<double>(eligibleCount(rows_, options_.eligible)) };
  if (comm_)
  {
    comm_->sum(total);
  }
  if (total[0] < 1)
  {
    return out;
  }

  if (!comm_ && static_cast<double>(options_.size) >= total[0])
  {
    // One process asked for every voxel: the strata would only order the same set.
    out.error = runShared(comm_, [&] { out = everyDistinctVector(); });
    return out;
  }

  std::vector<float> subsample;
  out.error = runShared(comm_, [&] { subsample = edgeSubsample(total[0]); });
  if (!out.error.empty())
  {
    return out;
  }
  if (comm_)
  {
    subsample = allGatherValues(*comm_, subsample);
  }
  const std::vector<float> edges = strataEdges(std::move(subsample));

  std::vector<double> mine;
  out.error = runShared(comm_, [&] { mine = assignStrata(edges); });
  if (!out.error.empty())
  {
    return out;
  }
  std::vector<double> all = mine;
  if (comm_)
  {
    comm_->sum(all);
  }

  std::vector<std::size_t> want = firstWants(mine, all);
  for (;;)
  {
    std::vector<char> proposal;
    out.error = runShared(comm_, [&] {
      fill(want);
      proposal = propose(want);
    });
    if (!out.error.empty())
    {
      return out;
    }
    std::vector<bool> more;
    if (decide(comm_ ? comm_->allGather(proposal) : proposal, more, out))
    {
      return out;
    }
    for (std::size_t i = 0; i < want.size(); ++i)
    {
      want[i] *= more[i] ? 2 : 1;
    }
  }
}
} // namespace

RowLayout RowLayout::plain(std::size_t n, std::int64_t first)
{
  RowLayout l;
  l.rows_ = n;
  l.first_ = first;
  return l;
}

RowLayout RowLayout::grid(const GridPiece& piece, const ImageGrid& block, int steps)
{
  RowLayout l;
  l.steps_ = std::max(steps, 1);
  l.rows_ = block.voxelCount() * static_cast<std::size_t>(l.steps_);
  l.grid_ = true;
  l.piece_ = piece;
  l.block_ = block;
  return l;
}

std::size_t RowLayout::ownedCount() const
{
  return grid_ ? piece_.ownedCount() * static_cast<std::size_t>(steps_) : rows_;
}

std::size_t RowLayout::stepRuns() const
{
  if (piece_.ownedCount() == 0)
  {
    return 0;
  }
  return static_cast<std::size_t>(piece_.ownedHi[1] - piece_.ownedLo[1] + 1) *
    static_cast<std::size_t>(piece_.ownedHi[2] - piece_.ownedLo[2] + 1);
}

std::size_t RowLayout::runCount() const
{
  if (!grid_)
  {
    return (rows_ + kPlainRun - 1) / kPlainRun;
  }
  return stepRuns() * static_cast<std::size_t>(steps_);
}

std::pair<std::size_t, std::size_t> RowLayout::runsWithin(std::size_t begin, std::size_t end) const
{
  // The first run r for which ends(r) holds; ends is false, then true, along the runs.
  const auto firstWhere = [this](auto ends) {
    std::size_t lo = 0, hi = runCount();
    while (lo < hi)
    {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (ends(run(mid)))
      {
        hi = mid;
      }
      else
      {
        lo = mid + 1;
      }
    }
    return lo;
  };
  const std::size_t first = firstWhere([begin](const Run& r) { return r.row + r.count > begin; });
  const std::size_t last = firstWhere([end](const Run& r) { return r.row >= end; });
  return { first, std::max(first, last) };
}

RowLayout::Run RowLayout::run(std::size_t r) const
{
  Run out;
  if (!grid_)
  {
    out.row = r * kPlainRun;
    out.global = first_ + static_cast<std::int64_t>(out.row);
    out.count = std::min(kPlainRun, rows_ - out.row);
    return out;
  }
  const std::size_t perStep = stepRuns();
  const std::size_t step = r / perStep;
  r %= perStep;
  const std::size_t ny = static_cast<std::size_t>(piece_.ownedHi[1] - piece_.ownedLo[1] + 1);
  const std::size_t j = static_cast<std::size_t>(piece_.ownedLo[1]) + r % ny;
  const std::size_t k = static_cast<std::size_t>(piece_.ownedLo[2]) + r / ny;
  const std::size_t nx = static_cast<std::size_t>(block_.dims[0]);
  out.row = (k * static_cast<std::size_t>(block_.dims[1]) + j) * nx + static_cast<std::size_t>(piece_.ownedLo[0]);
  out.global = piece_.globalIndex(static_cast<std::int64_t>(out.row), block_);
  out.count = static_cast<std::size_t>(piece_.ownedHi[0] - piece_.ownedLo[0] + 1);
  if (step > 0)
  {
    const std::size_t wholeVoxels = static_cast<std::size_t>(piece_.wholeDims[0]) *
      static_cast<std::size_t>(piece_.wholeDims[1]) * static_cast<std::size_t>(piece_.wholeDims[2]);
    out.row += step * block_.voxelCount();
    out.global += static_cast<std::int64_t>(step * wholeVoxels);
  }
  return out;
}

std::size_t eligibleCount(const RowLayout& rows, const unsigned char* eligible)
{
  if (!eligible)
  {
    return rows.ownedCount();
  }
  std::size_t count = 0;
  const long long runs = static_cast<long long>(rows.runCount());
#pragma omp parallel for schedule(static) reduction(+ : count)
  for (long long r = 0; r < runs; ++r)
  {
    const RowLayout::Run run = rows.run(static_cast<std::size_t>(r));
    for (std::size_t t = 0; t < run.count; ++t)
    {
      count += eligible[run.row + t] != 0 ? 1 : 0;
    }
  }
  return count;
}

std::uint64_t sampleKey(std::uint64_t seed, std::int64_t globalIndex)
{
  return mix64(static_cast<std::uint64_t>(globalIndex) + mix64(seed + 0x9E3779B97F4A7C15ull));
}

std::vector<std::uint32_t> uniformLandmarks(std::size_t n, int L, std::uint64_t seed)
{
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::uint64_t state = seed ^ 0x1505ull;
  for (std::size_t i = 0; i < static_cast<std::size_t>(L); ++i)
  {
    std::swap(order[i], order[i + uniformIndex(state, static_cast<std::uint64_t>(n - i))]);
  }
  order.resize(static_cast<std::size_t>(L));
  return order;
}

std::string sharedError(const Communicator* comm, const std::string& localError)
{
  if (!isDistributed(comm))
  {
    return localError;
  }
  if (allTrue(comm, localError.empty()))
  {
    return {};
  }
  // Some process failed: all learn the first one's message (one string per process).
  std::vector<char> mine(localError.begin(), localError.end());
  mine.push_back('\0');
  const std::vector<char> all = comm->allGather(mine);
  auto at = all.begin();
  for (int rank = 0; at != all.end(); ++rank)
  {
    const auto end = std::find(at, all.end(), '\0');
    if (end != at)
    {
      return "Process " + std::to_string(rank) + " of " + std::to_string(comm->size()) + ": " + std::string(at, end);
    }
    at = end == all.end() ? end : end + 1;
  }
  return "A process failed.";
}

ReferenceSample drawReferenceSample(FeatureRows& source, const RowLayout& rows, const std::vector<int>& columns,
  const std::vector<double>& center, const ReferenceSampleOptions& options, const Communicator* comm)
{
  Sampler sampler(source, rows, columns, center, options, comm);
  ReferenceSample sample = sampler.draw();
  sample.warnings = sampler.warnings();
  return sample;
}

ReferenceSample drawReferenceSample(const float* data, int dim, const RowLayout& rows,
  const std::vector<int>& columns, const std::vector<double>& center, const ReferenceSampleOptions& options,
  const Communicator* comm)
{
  MatrixRows source(data, rows.size(), dim);
  return drawReferenceSample(source, rows, columns, center, options, comm);
}

std::vector<std::int64_t> drawReferenceSample(const float* data, std::size_t n, int dim,
  const std::vector<int>& columns, const std::vector<double>& center, const ReferenceSampleOptions& options)
{
  return drawReferenceSample(data, dim, RowLayout::plain(n), columns, center, options, nullptr).indices;
}

} // namespace mcv
