#include "FeatureBricks.h"

#include "HalfCoordinates.h"
#include "TypedChannel.h"

#ifdef MCV_HAS_CUDA
#include "cuda/FusedPassesCuda.h"
#include "cuda/FusedPlacementCuda.h"
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mcv
{

namespace
{
std::size_t scalarBytes(ScalarType t)
{
  switch (t)
  {
    case ScalarType::Int8:
    case ScalarType::UInt8:
      return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16:
      return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32:
      return 4;
    case ScalarType::Float64:
      return 8;
  }
  return 0;
}

// The channel from voxel `first` on.
ChannelView fromVoxel(ChannelView c, std::size_t first)
{
  c.data = static_cast<const char*>(c.data) +
    first * static_cast<std::size_t>(c.numComponents) * scalarBytes(c.type);
  return c;
}

inline int clampIndex(int i, int n)
{
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

std::size_t sliceVoxels(const ImageGrid& g)
{
  return static_cast<std::size_t>(g.dims[0]) * static_cast<std::size_t>(g.dims[1]);
}

#ifdef MCV_HAS_CUDA
// The host's part of every GPU pass: a slab's channels as float (what rawSlab converts).
cuda::FusedChannelFill channelFill(const std::vector<ChannelView>& channels)
{
  return [&channels](int c, std::size_t first, std::size_t count, float* values) {
    return detail::channelToFloat(fromVoxel(channels[static_cast<std::size_t>(c)], first), count, values, nullptr);
  };
}

// A GPU pass over the channels; offset and scale empty for the statistics pass.
cuda::FusedPassSetup passSetup(const ImageGrid& grid, std::size_t channels, const FeatureSelection& selection,
  int cols, const std::vector<double>& offset, const std::vector<double>& scale, std::size_t deviceBytes,
  cuda::ResidentChannels* resident)
{
  cuda::FusedPassSetup setup;
  setup.grid = grid;
  setup.channels = static_cast<int>(channels);
  setup.selection = selection;
  setup.cols = cols;
  setup.offset = offset;
  setup.scale = scale;
  setup.deviceBytes = deviceBytes;
  setup.resident = resident;
  return setup;
}

FeatureBricks::DeviceStats statsOf(const cuda::FusedPassStats& p)
{
  return FeatureBricks::DeviceStats{ p.slabSlices, p.slabs, p.bytesToDevice, p.bytesFromDevice, p.deviceBytes,
    p.deviceUsedPeak, p.pinnedBytes, p.setupMs, p.fillMs, p.waitMs, p.totalMs };
}

cuda::ResidentChannels* residentOf(const std::shared_ptr<void>& resident)
{
  return static_cast<cuda::ResidentChannels*>(resident.get());
}
#endif

// Voxels gathered per batch: their 3x3x3 neighbourhoods (27 voxels each, F features) stay
// a few MiB.
constexpr std::size_t kGatherBatch = 4096;
// ... and at least this many: smaller batches cost more in setup than they share out.
constexpr std::size_t kGatherBatchMin = 128;

// The batch size for n voxels: kGatherBatch, or smaller so that every thread gets about four
// batches (the sample's gathers are mostly a few thousand voxels: one batch of 4096 left
// all but one thread idle).
std::size_t gatherBatch(std::size_t n)
{
#ifdef _OPENMP
  const std::size_t threads = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
#else
  const std::size_t threads = 1;
#endif
  return std::max(kGatherBatchMin, std::min(kGatherBatch, n / (4 * threads)));
}
} // namespace

FeatureBricks::FeatureBricks(const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const FeatureOptions& options, std::size_t slabBytes)
  : channels_(channels)
  , grid_(grid)
  , options_(options)
  , selection_(FeatureSelection::forPreset(options.preset, options.custom))
  , cols_(featureCount(channels.size(), options))
  , slices_(slicesFor(grid, featureCount(channels.size(), options),
      slabBytes == kScaledSlab ? slabBytesFor(grid, options.piece, featureCount(channels.size(), options)) : slabBytes))
{
  if (options_.channelNames.empty())
  {
    for (std::size_t c = 0; c < channels_.size(); ++c)
    {
      options_.channelNames.push_back("ch" + std::to_string(c + 1));
    }
  }
}

int FeatureBricks::slicesFor(const ImageGrid& grid, int features, std::size_t slabBytes)
{
  const std::size_t perSlice = sliceVoxels(grid) * static_cast<std::size_t>(std::max(1, features)) * sizeof(float);
  const std::size_t slices = perSlice > 0 ? slabBytes / perSlice : 1;
  return static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(slices, static_cast<std::size_t>(std::max(1, grid.dims[2])))));
}

std::size_t FeatureBricks::slabBytesFor(const ImageGrid& grid, const GridPiece& piece, int features)
{
  const GridPiece owned = piece.wholeDims[0] > 0 ? piece : GridPiece::whole(grid);
  const double whole = static_cast<double>(GridPiece::whole(ImageGrid{ owned.wholeDims }).ownedCount());
  const double share = whole > 0 ? std::min(1.0, static_cast<double>(owned.ownedCount()) / whole) : 1.0;
  const std::size_t shared = static_cast<std::size_t>(share * static_cast<double>(kDefaultSlabBytes));
  const std::size_t fourSlices =
    4 * sliceVoxels(grid) * static_cast<std::size_t>(std::max(1, features)) * sizeof(float);
  return std::min(kDefaultSlabBytes, std::max(shared, fourSlices));
}

std::size_t FeatureBricks::workingBytes(const ImageGrid& grid, int features, std::size_t slabBytes)
{
  const std::size_t slices = static_cast<std::size_t>(slicesFor(grid, features, slabBytes));
  const std::size_t withGhosts = (slices + 2) * sliceVoxels(grid);
  // Features, one float channel and its non-finite mask over the slab with its ghosts; the
  // row masks of the slab itself; the gathered neighbourhoods of a batch.
  return withGhosts * (static_cast<std::size_t>(features) * sizeof(float) + sizeof(float) + 1) +
    2 * slices * sliceVoxels(grid) + kGatherBatch * 27 * (static_cast<std::size_t>(features) + 1) * sizeof(float);
}

std::size_t FeatureBricks::workingBytes() const
{
  const std::size_t slabBytes = static_cast<std::size_t>(slices_) * sliceVoxels(grid_) *
    static_cast<std::size_t>(std::max(1, cols_)) * sizeof(float);
  return workingBytes(grid_, cols_, slabBytes);
}

std::size_t FeatureBricks::blockCount() const
{
  return grid_.voxelCount() == 0 ? 0 : static_cast<std::size_t>((grid_.dims[2] + slices_ - 1) / slices_);
}

std::size_t FeatureBricks::blockBegin(std::size_t b) const
{
  const std::size_t z = std::min(b * static_cast<std::size_t>(slices_), static_cast<std::size_t>(grid_.dims[2]));
  return z * sliceVoxels(grid_);
}

float* FeatureBricks::rawSlab(int z0, int z1, std::vector<double>* badPerChannel)
{
  const int g0 = std::max(0, z0 - 1), g1 = std::min(grid_.dims[2], z1 + 1);
  ImageGrid sub = grid_;
  sub.dims[2] = g1 - g0;
  const std::size_t nxy = sliceVoxels(grid_), n = sub.voxelCount();
  const std::size_t first = static_cast<std::size_t>(z0 - g0) * nxy;
  const std::size_t count = static_cast<std::size_t>(z1 - z0) * nxy;
  features_.resize(n * static_cast<std::size_t>(cols_));
  values_.resize(n);
  bad_.assign(count, 0);
  const FeatureOutput out{ features_.data(), n, cols_ };
  const GridPiece piece = options_.piece.wholeDims[0] > 0 ? options_.piece : GridPiece::whole(grid_);
  const int nx = grid_.dims[0];
  for (std::size_t c = 0; c < channels_.size(); ++c)
  {
    channelBad_.assign(n, 0);
    const std::size_t bad = detail::channelToFloat(
      fromVoxel(channels_[c], static_cast<std::size_t>(g0) * nxy), n, values_.data(), channelBad_.data());
    if (bad > 0)
    {
      for (std::size_t r = 0; r < count; ++r)
      {
        if (channelBad_[first + r])
        {
          bad_[r] = 1;
          const int k = z0 + static_cast<int>(r / nxy), j = static_cast<int>((r % nxy) / nx), i = static_cast<int>(r % nx);
          if (badPerChannel && piece.owns(i, j, k))
          {
            (*badPerChannel)[c] += 1;
          }
        }
      }
    }
    detail::channelFeaturesCPU(values_.data(), bad > 0, sub, selection_, out, static_cast<int>(c) * selection_.perChannel());
  }
  return features_.data() + first * static_cast<std::size_t>(cols_);
}

bool FeatureBricks::prepare(FeatureResult& result)
{
  result = FeatureResult();
  const Communicator* comm = options_.communicator;
  result.error = detail::checkInput(channels_, grid_, options_);
  if (!allTrue(comm, result.error.empty()))
  {
    if (result.error.empty())
    {
      result.error = "another process of the parallel run reported an error";
    }
    return false;
  }
  result.names = featureNames(options_.channelNames, selection_);
  result.deviceUsed = Device::CPU;
  if (!options_.givenOffset.empty() || !options_.givenScale.empty())
  {
    // Checked before anything runs; the same answer on every process (same options).
    if (options_.givenOffset.size() != static_cast<std::size_t>(cols_) ||
      options_.givenScale.size() != static_cast<std::size_t>(cols_))
    {
      result.error = "the given normalisation has " + std::to_string(options_.givenOffset.size()) + " offsets and " +
        std::to_string(options_.givenScale.size()) + " scales for " + std::to_string(cols_) + " feature columns";
      return false;
    }
    result.columnOffset = offset_ = options_.givenOffset;
    result.columnScale = scale_ = options_.givenScale;
    if (options_.progress)
    {
      options_.progress(1.0);
    }
    return true;
  }
  const GridPiece piece = options_.piece.wholeDims[0] > 0 ? options_.piece : GridPiece::whole(grid_);
  const bool zscore = options_.normalization == FeatureNormalization::ZScore;
  const std::size_t nxy = sliceVoxels(grid_);
  const int nx = grid_.dims[0];
  std::vector<detail::ColumnStats> parts;
  std::vector<double> badPerChannel(channels_.size(), 0.0);
  double badVoxels = 0;
  std::string deviceError;
  if (deviceStatistics(parts, badPerChannel, badVoxels, deviceError))
  {
    result.deviceUsed = Device::GPU;
  }
  else if (!deviceError.empty())
  {
    result.warnings.push_back("The GPU statistics pass failed (" + deviceError + "); it ran on the CPU.");
  }
  std::vector<unsigned char> statsMask;
  const std::size_t blocks = result.deviceUsed == Device::GPU ? 0 : blockCount();
  for (std::size_t b = 0; b < blocks; ++b)
  {
    if (options_.progress)
    {
      options_.progress(static_cast<double>(b) / static_cast<double>(blocks));
    }
    const int z0 = static_cast<int>(b) * slices_, z1 = std::min(grid_.dims[2], z0 + slices_);
    float* rows = rawSlab(z0, z1, &badPerChannel);
    const std::size_t count = static_cast<std::size_t>(z1 - z0) * nxy;
    // The statistics count each owned, finite voxel once (as computeFeatures does).
    statsMask.resize(count);
    for (std::size_t r = 0; r < count; ++r)
    {
      const int k = z0 + static_cast<int>(r / nxy), j = static_cast<int>((r % nxy) / nx), i = static_cast<int>(r % nx);
      const bool owned = piece.owns(i, j, k);
      statsMask[r] = (!owned || bad_[r]) ? 1 : 0;
      badVoxels += (owned && bad_[r]) ? 1.0 : 0.0;
    }
    parts.emplace_back();
    detail::columnStatsCPU(FeatureOutput{ rows, count, cols_ }, statsMask.data(), zscore, parts.back());
  }
  const detail::VolumeStats volume = detail::combineStats(detail::mergeStats(parts), badPerChannel, badVoxels,
    static_cast<double>(piece.ownedCount()), comm);
  detail::normalizationFromStats(options_.normalization, volume.columns, result);
  statistics_ = volume.columns;
  offset_ = result.columnOffset;
  scale_ = result.columnScale;
  result.nonFiniteVoxels = static_cast<std::size_t>(volume.badVoxels);
  detail::addStatsWarnings(volume, options_, detail::overflowCount(volume), result);
  if (options_.progress)
  {
    options_.progress(1.0);
  }
  return true;
}

const float* FeatureBricks::block(std::size_t b)
{
  const int z0 = static_cast<int>(b) * slices_, z1 = std::min(grid_.dims[2], z0 + slices_);
  float* rows = rawSlab(z0, z1, nullptr);
  const std::size_t count = static_cast<std::size_t>(z1 - z0) * sliceVoxels(grid_);
  detail::applyNormalizationCPU(FeatureOutput{ rows, count, cols_ }, bad_.data(), offset_, scale_);
  return rows;
}

void FeatureBricks::gather(const std::size_t* index, std::size_t n, float* out)
{
  const int nx = grid_.dims[0], ny = grid_.dims[1], nz = grid_.dims[2];
  const std::size_t F = static_cast<std::size_t>(cols_);
  // Batches on separate threads (the sample's candidates run to millions of voxels in a giga-
  // voxel volume with repeated content); the feature code inside each runs on its thread.
  const std::size_t batchSize = gatherBatch(n);
  const long long batches = static_cast<long long>((n + batchSize - 1) / batchSize);
#pragma omp parallel if (batches > 1)
  {
  std::vector<float> values;
  std::vector<unsigned char> bad;
#pragma omp for schedule(dynamic)
  for (long long batch = 0; batch < batches; ++batch)
  {
    const std::size_t at = static_cast<std::size_t>(batch) * batchSize;
    const std::size_t m = std::min(batchSize, n - at);
    // The neighbourhoods side by side along x: voxel b's is x in [3b, 3b + 3), so its centre
    // (3b + 1, 1, 1) sees only its own neighbours, border-replicated as in the volume.
    ImageGrid tiny = grid_;
    tiny.dims = { static_cast<int>(3 * m), 3, 3 };
    const std::size_t tn = tiny.voxelCount(), row = 3 * m;
    values.resize(tn);
    bad.assign(m, 0);
    for (std::size_t c = 0; c < channels_.size(); ++c)
    {
      bool anyBad = false;
      const ChannelView& view = channels_[c];
      withTypedData(view, [&](const auto* data) {
        for (std::size_t b = 0; b < m; ++b)
        {
          const std::int64_t v = static_cast<std::int64_t>(index[at + b]);
          const int i = static_cast<int>(v % nx), j = static_cast<int>((v / nx) % ny), k = static_cast<int>(v / (static_cast<std::int64_t>(nx) * ny));
          for (int dz = 0; dz < 3; ++dz)
          {
            for (int dy = 0; dy < 3; ++dy)
            {
              for (int dx = 0; dx < 3; ++dx)
              {
                const std::int64_t src = clampIndex(i + dx - 1, nx) +
                  static_cast<std::int64_t>(nx) * (clampIndex(j + dy - 1, ny) + static_cast<std::int64_t>(ny) * clampIndex(k + dz - 1, nz));
                const float x = static_cast<float>(data[src * view.numComponents + view.component]);
                values[3 * b + static_cast<std::size_t>(dx) + row * static_cast<std::size_t>(dy + 3 * dz)] = x;
                if (!std::isfinite(x))
                {
                  anyBad = true;
                  bad[b] |= (dx == 1 && dy == 1 && dz == 1) ? 1 : 0;
                }
              }
            }
          }
        }
      });
      // The centres alone: the other 26 voxels of each neighbourhood are inputs only.
      detail::channelFeaturesCentresCPU(values.data(), anyBad, tiny, selection_, FeatureOutput{ out + at * F, m, cols_ },
        static_cast<int>(c) * selection_.perChannel());
    }
    detail::applyNormalizationCPU(FeatureOutput{ out + at * F, m, cols_ }, bad.data(), offset_, scale_);
  }
  }
}

bool FeatureBricks::recordDevicePass(const char* name, const DeviceStats& stats, bool ok, std::string& error)
{
  devicePasses_.push_back(DevicePass{ name, ok, stats });
  if (!ok && error.empty())
  {
    error = "unknown CUDA failure";
  }
  return ok;
}

int FeatureBricks::passesOnDevice() const
{
  return static_cast<int>(std::count_if(devicePasses_.begin(), devicePasses_.end(),
    [](const DevicePass& p) { return p.ok && p.name != "placement"; }));
}

bool FeatureBricks::normalisedPassesApply() const
{
  return offset_.size() == static_cast<std::size_t>(cols_) && wholeVolumeHere();
}

bool FeatureBricks::wholeVolumeHere() const
{
  const GridPiece& piece = options_.piece;
  return !isDistributed(options_.communicator) && (piece.wholeDims[0] <= 0 || piece.isWhole(grid_));
}

bool FeatureBricks::deviceStatistics(std::vector<detail::ColumnStats>& parts, std::vector<double>& badPerChannel,
  double& badVoxels, std::string& error)
{
#ifdef MCV_HAS_CUDA
  if (!wholeVolumeHere() || resolveDevice(options_.device) != Device::GPU)
  {
    return false;
  }
  // The channels stay on the device for the later passes when they fit.
  std::shared_ptr<cuda::ResidentChannels> resident = std::make_shared<cuda::ResidentChannels>();
  if (resident->reserveIfFits(static_cast<int>(channels_.size()), grid_.voxelCount(), deviceBytes_))
  {
    resident_ = resident;
  }
  cuda::RawStatistics raw;
  cuda::FusedPassStats stats;
  const bool ok = cuda::fusedRawStatistics(
    passSetup(grid_, channels_.size(), selection_, cols_, {}, {}, deviceBytes_, residentOf(resident_)), channelFill(channels_),
    &raw, options_.progress, &stats, &error);
  if (!recordDevicePass("statistics", statsOf(stats), ok, error))
  {
    resident_.reset();
    return false;
  }
  parts = std::move(raw.slabs);
  badPerChannel = std::move(raw.badPerChannel);
  badVoxels = raw.badVoxels;
  return true;
#else
  (void)parts;
  (void)badPerChannel;
  (void)badVoxels;
  (void)error;
  return false;
#endif
}

#ifdef MCV_HAS_CUDA
template <class Pass>
bool FeatureBricks::normalisedDevicePass(const char* name, std::string& error, Pass pass)
{
  if (!normalisedPassesApply())
  {
    return false;
  }
  const cuda::FusedPassSetup setup =
    passSetup(grid_, channels_.size(), selection_, cols_, offset_, scale_, deviceBytes_, residentOf(resident_));
  cuda::FusedPassStats stats;
  const bool ok = pass(setup, &stats, &error);
  recordDevicePass(name, statsOf(stats), ok, error);
  return true;
}
#endif

DeviceColumnSums FeatureBricks::columnSumsOnDevice(const std::function<void(double)>& progress)
{
  DeviceColumnSums out;
#ifdef MCV_HAS_CUDA
  out.attempted = normalisedDevicePass("column sums", out.error,
    [&](const cuda::FusedPassSetup& setup, cuda::FusedPassStats* stats, std::string* error)
    { return cuda::fusedColumnSums(setup, channelFill(channels_), &out, progress, stats, error); });
#else
  (void)progress;
#endif
  return out;
}

DevicePassReport FeatureBricks::strataOnDevice(const DeviceStrata& request)
{
  DevicePassReport out;
#ifdef MCV_HAS_CUDA
  out.attempted = normalisedDevicePass("strata", out.error,
    [&](const cuda::FusedPassSetup& setup, cuda::FusedPassStats* stats, std::string* error)
    { return cuda::fusedStrata(setup, channelFill(channels_), request, stats, error); });
#else
  (void)request;
#endif
  return out;
}

DevicePlacementReport FeatureBricks::placeOnDevice(const DevicePlacement& request)
{
  DevicePlacementReport report;
  deviceStats_ = DeviceStats();
#ifdef MCV_HAS_CUDA
  if (offset_.size() != static_cast<std::size_t>(cols_))
  {
    return report; // not prepared
  }
  report.attempted = true;
  cuda::FusedPlacementSetup setup;
  setup.grid = grid_;
  setup.channels = static_cast<int>(channels_.size());
  setup.selection = selection_;
  setup.cols = cols_;
  setup.offset = offset_;
  setup.scale = scale_;
  setup.deviceBytes = deviceBytes_;
  setup.resident = residentOf(resident_);
  cuda::PlacementInput& r = setup.references;
  r.refX = request.refX;
  r.refY = request.refY;
  r.M = request.M;
  r.D = request.D;
  r.d = request.d;
  r.dim = cols_;
  r.columns = request.columns;
  r.neighbors = request.neighbors;
  r.regularization = request.regularization;
  r.distanceMargin = request.distanceMargin;
  const cuda::FusedChannelFill fill = channelFill(channels_);
  if (request.outHalf)
  {
    // float16 output: each slab's coordinates are rounded from the pinned staging buffer.
    std::uint16_t* const halves = request.outHalf;
    const std::size_t d = static_cast<std::size_t>(request.d);
    std::size_t& overflow = report.halfOverflow;
    setup.writeCoordinates = [halves, d, &overflow](std::size_t first, std::size_t rows, const float* values) {
      overflow += floatsToHalves(values, rows * d, halves + first * d);
    };
  }
  if (request.distance)
  {
    float* const distance = request.distance;
    setup.modelRadius = request.modelRadius;
    setup.writeDistances = [distance](std::size_t first, std::size_t rows, const float* values) {
      std::copy(values, values + rows, distance + first);
    };
  }
  cuda::FusedPlacementStats stats;
  std::string error;
  const bool ok = cuda::placeFused(setup, fill, request.out, request.progress, &stats, &report.rowsDone, &error);
  resident_.reset(); // the last pass over the volume
  report.radiusScans = stats.radiusScans;
  deviceStats_ = DeviceStats{ stats.slabSlices, stats.slabs, stats.bytesToDevice, stats.bytesFromDevice,
    stats.deviceBytes, stats.deviceUsedPeak, stats.pinnedBytes, stats.setupMs, stats.fillMs, stats.waitMs,
    stats.totalMs };
  if (!recordDevicePass("placement", deviceStats_, ok, error))
  {
    report.error = error;
  }
#else
  (void)request;
#endif
  return report;
}

} // namespace mcv
