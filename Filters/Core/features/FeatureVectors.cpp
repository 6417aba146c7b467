#include "FeatureVectors.h"
#include "EnumNames.h"
#include "TypedChannel.h"

#ifdef MCV_HAS_CUDA
#include "cuda/FeaturesCuda.h"
#endif

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace mcv
{

FeatureSelection FeatureSelection::forPreset(FeaturePreset preset, const FeatureSelection& custom)
{
  FeatureSelection s;
  switch (preset)
  {
    case FeaturePreset::SixD:
      s.intensity = true;
      s.gradient = false;
      s.gradientMagnitude = true;
      s.laplacian = s.localMean = s.localVariance = false;
      return s;
    case FeaturePreset::TwentyFourD:
      s.intensity = s.gradient = s.gradientMagnitude = true;
      s.laplacian = s.localMean = s.localVariance = true;
      return s;
    case FeaturePreset::Custom:
      return custom;
  }
  return s;
}

int featureCount(std::size_t channels, const FeatureOptions& options)
{
  return static_cast<int>(channels) *
    FeatureSelection::forPreset(options.preset, options.custom).perChannel();
}

std::vector<std::string> featureNames(
  const std::vector<std::string>& channelNames, const FeatureSelection& selection)
{
  std::vector<std::string> names;
  for (const std::string& c : channelNames)
  {
    if (selection.intensity)
      names.push_back(c + ".intensity");
    if (selection.gradient)
    {
      names.push_back(c + ".gradX");
      names.push_back(c + ".gradY");
      names.push_back(c + ".gradZ");
    }
    if (selection.gradientMagnitude)
      names.push_back(c + ".gradMag");
    if (selection.laplacian)
      names.push_back(c + ".laplacian");
    if (selection.localMean)
      names.push_back(c + ".mean");
    if (selection.localVariance)
      names.push_back(c + ".variance");
  }
  return names;
}

namespace
{
const EnumName<FeatureNormalization> kNormalizationNames[] = {
  { FeatureNormalization::ZScore, "ZScore" }, { FeatureNormalization::MinMax, "MinMax" },
  { FeatureNormalization::None, "None" }
};
const EnumName<FeaturePreset> kPresetNames[] = { { FeaturePreset::SixD, "6D" },
  { FeaturePreset::TwentyFourD, "24D" }, { FeaturePreset::Custom, "Custom" } };
}

const char* normalizationName(FeatureNormalization n)
{
  return nameOf(kNormalizationNames, n, "unknown");
}

const char* presetName(FeaturePreset p)
{
  return nameOf(kPresetNames, p, "unknown");
}

bool normalizationNamed(const std::string& name, FeatureNormalization& normalization)
{
  return valueOf(kNormalizationNames, name, normalization);
}

bool presetNamed(const std::string& name, FeaturePreset& preset)
{
  return valueOf(kPresetNames, name, preset);
}

namespace
{
// True when the grid is one process's block of a larger volume (or holds ghost voxels).
bool isPartialBlock(const GridPiece& piece, const ImageGrid& grid)
{
  return piece.wholeDims[0] > 0 && !piece.isWhole(grid);
}
} // namespace

namespace detail
{

void ColumnStats::reset(int cols)
{
  const std::size_t c = static_cast<std::size_t>(cols);
  count.assign(c, 0.0);
  sum.assign(c, 0.0);
  min.assign(c, std::numeric_limits<double>::infinity());
  max.assign(c, -std::numeric_limits<double>::infinity());
  sqdev.assign(c, 0.0);
}

std::size_t channelToFloat(
  const ChannelView& channel, std::size_t n, float* values, unsigned char* mask)
{
  std::size_t bad = 0;
  withTypedData(channel, [&](auto data) {
    const std::int64_t count = static_cast<std::int64_t>(n);
    const int stride = channel.numComponents, offset = channel.component;
    std::size_t localBad = 0;
#pragma omp parallel for reduction(+ : localBad) schedule(static)
    for (std::int64_t v = 0; v < count; ++v)
    {
      const float x = static_cast<float>(data[v * stride + offset]);
      values[v] = x;
      if (!std::isfinite(x))
      {
        ++localBad;
        if (mask)
        {
          mask[v] = 1;
        }
      }
    }
    bad = localBad;
  });
  return bad;
}

namespace
{

inline int clampIndex(int i, int n)
{
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

// The constants of one channel's feature loop.
struct FeatureLoop
{
  FeatureLoop(const ImageGrid& grid, const FeatureSelection& s)
    : sel(s)
    , nx(grid.dims[0])
    , sx(static_cast<float>(0.5 / grid.spacing[0]))
    , sy(static_cast<float>(0.5 / grid.spacing[1]))
    , sz(static_cast<float>(0.5 / grid.spacing[2]))
    , perChannel(s.perChannel())
    , needNeighbourhood(s.localMean || s.localVariance)
    , needGradient(s.gradient || s.gradientMagnitude)
  {
  }
  const FeatureSelection& sel;
  int nx;
  float sx, sy, sz;
  int perChannel;
  bool needNeighbourhood, needGradient;
};

// Voxel i of the x-line whose 3 x 3 neighbouring lines (rows[dz + 1][dy + 1], border-clamped)
// are given: its features of one channel into o[0, perChannel). The one body of the whole-
// volume loop and of the single voxels' (channelFeaturesCentresCPU), so both give the same bits.
template <bool Guard>
inline void voxelFeatures(const float* const (&rows)[3][3], int i, const FeatureLoop& p, float* o)
{
  const FeatureSelection& sel = p.sel;
  const int nx = p.nx;
  const float c = rows[1][1][i];
  if (Guard && !std::isfinite(c))
  {
    std::fill(o, o + p.perChannel, 0.0f);
    return;
  }
  // A non-finite neighbour counts as the centre value (like a replicated border).
  auto at = [c](const float* r, int ii) {
    const float v = r[ii];
    return (!Guard || std::isfinite(v)) ? v : c;
  };
  const int im = i > 0 ? i - 1 : 0, ip = i + 1 < nx ? i + 1 : nx - 1;
  const float xm = at(rows[1][1], im), xp = at(rows[1][1], ip);
  const float ym = at(rows[1][0], i), yp = at(rows[1][2], i);
  const float zm = at(rows[0][1], i), zp = at(rows[2][1], i);
  int col = 0;
  if (sel.intensity)
  {
    o[col++] = c;
  }
  if (p.needGradient)
  {
    const float gx = (xp - xm) * p.sx, gy = (yp - ym) * p.sy, gz = (zp - zm) * p.sz;
    if (sel.gradient)
    {
      o[col++] = gx;
      o[col++] = gy;
      o[col++] = gz;
    }
    if (sel.gradientMagnitude)
    {
      o[col++] = std::sqrt(gx * gx + gy * gy + gz * gz);
    }
  }
  if (sel.laplacian)
  {
    o[col++] = ((xm + xp) + (ym + yp) + (zm + zp)) / 6.0f - c;
  }
  if (p.needNeighbourhood)
  {
    const int is[3] = { im, i, ip };
    float v[27];
    float s = 0.0f;
    int t = 0;
    for (int a = 0; a < 3; ++a)
    {
      for (int b = 0; b < 3; ++b)
      {
        for (int d = 0; d < 3; ++d, ++t)
        {
          v[t] = at(rows[a][b], is[d]);
          s += v[t];
        }
      }
    }
    const float mean = s / 27.0f;
    if (sel.localMean)
    {
      o[col++] = mean;
    }
    if (sel.localVariance)
    {
      float s2 = 0.0f;
      for (t = 0; t < 27; ++t)
      {
        const float dv = v[t] - mean;
        s2 += dv * dv;
      }
      o[col++] = s2 / 27.0f;
    }
  }
}

// The pointers to the 3 x 3 x-lines around line (j, k), border-clamped.
inline void neighbourLines(const float* f, const ImageGrid& grid, int j, int k, const float* (&rows)[3][3])
{
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  const std::size_t nxy = static_cast<std::size_t>(nx) * ny;
  for (int dz = -1; dz <= 1; ++dz)
  {
    const std::size_t kk = static_cast<std::size_t>(clampIndex(k + dz, nz));
    for (int dy = -1; dy <= 1; ++dy)
    {
      const std::size_t jj = static_cast<std::size_t>(clampIndex(j + dy, ny));
      rows[dz + 1][dy + 1] = f + kk * nxy + jj * static_cast<std::size_t>(nx);
    }
  }
}

template <bool Guard>
void channelFeaturesImpl(const float* f, const ImageGrid& grid, const FeatureSelection& sel,
  const FeatureOutput& out, int firstColumn)
{
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  const std::size_t nxy = static_cast<std::size_t>(nx) * ny;
  const std::size_t F = static_cast<std::size_t>(out.cols);
  const FeatureLoop loop(grid, sel);

#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < nz; ++k)
  {
    for (int j = 0; j < ny; ++j)
    {
      const float* rows[3][3]; // [dz + 1][dy + 1]
      neighbourLines(f, grid, j, k, rows);
      float* dst = out.data +
        (static_cast<std::size_t>(k) * nxy + static_cast<std::size_t>(j) * nx) * F + firstColumn;
      for (int i = 0; i < nx; ++i)
      {
        voxelFeatures<Guard>(rows, i, loop, dst + static_cast<std::size_t>(i) * F);
      }
    }
  }
}

template <bool Guard>
void channelFeaturesCentresImpl(const float* f, const ImageGrid& grid, const FeatureSelection& sel,
  const FeatureOutput& out, int firstColumn)
{
  const std::size_t F = static_cast<std::size_t>(out.cols);
  const FeatureLoop loop(grid, sel);
  const float* rows[3][3];
  neighbourLines(f, grid, 1, 1, rows);
  for (std::size_t b = 0; b < out.rows; ++b)
  {
    voxelFeatures<Guard>(rows, static_cast<int>(3 * b + 1), loop, out.data + b * F + firstColumn);
  }
}

} // namespace

void channelFeaturesCPU(const float* values, bool hasNonFinite, const ImageGrid& grid,
  const FeatureSelection& selection, const FeatureOutput& out, int firstColumn)
{
  if (hasNonFinite)
  {
    channelFeaturesImpl<true>(values, grid, selection, out, firstColumn);
  }
  else
  {
    channelFeaturesImpl<false>(values, grid, selection, out, firstColumn);
  }
}

void channelFeaturesCentresCPU(const float* values, bool hasNonFinite, const ImageGrid& grid,
  const FeatureSelection& selection, const FeatureOutput& out, int firstColumn)
{
  (hasNonFinite ? channelFeaturesCentresImpl<true> : channelFeaturesCentresImpl<false>)(
    values, grid, selection, out, firstColumn);
}

namespace
{
// One OpenMP pass over the rows of out that mask does not exclude: each thread folds every
// finite value into its own Local (add(local, column, value)), then merge(local) combines it
// into the result, one thread at a time.
template <class Local, class Add, class Merge>
void foldFiniteColumns(const FeatureOutput& out, const unsigned char* mask, const Local& empty,
  Add add, Merge merge)
{
  const int F = out.cols;
  const std::int64_t n = static_cast<std::int64_t>(out.rows);
#pragma omp parallel
  {
    Local local = empty;
#pragma omp for schedule(static)
    for (std::int64_t r = 0; r < n; ++r)
    {
      if (mask && mask[r])
      {
        continue;
      }
      const float* row = out.data + static_cast<std::size_t>(r) * F;
      for (int c = 0; c < F; ++c)
      {
        const double x = row[c];
        if (std::isfinite(x))
        {
          add(local, c, x);
        }
      }
    }
#pragma omp critical(mcvFeatureStats)
    merge(local);
  }
}
} // namespace

void columnStatsCPU(
  const FeatureOutput& out, const unsigned char* mask, bool deviation, ColumnStats& stats)
{
  const int F = out.cols;
  stats.reset(F);
  ColumnStats empty;
  empty.reset(F);
  foldFiniteColumns(out, mask, empty,
    [](ColumnStats& local, int c, double x)
    {
      local.count[c] += 1.0;
      local.sum[c] += x;
      local.min[c] = std::min(local.min[c], x);
      local.max[c] = std::max(local.max[c], x);
    },
    [&](const ColumnStats& local)
    {
      for (int c = 0; c < F; ++c)
      {
        stats.count[c] += local.count[c];
        stats.sum[c] += local.sum[c];
        stats.min[c] = std::min(stats.min[c], local.min[c]);
        stats.max[c] = std::max(stats.max[c], local.max[c]);
      }
    });
  if (!deviation)
  {
    return;
  }
  std::vector<double> mean(static_cast<std::size_t>(F), 0.0);
  for (int c = 0; c < F; ++c)
  {
    mean[c] = stats.count[c] > 0 ? stats.sum[c] / stats.count[c] : 0.0;
  }
  foldFiniteColumns(out, mask, std::vector<double>(static_cast<std::size_t>(F), 0.0),
    [&](std::vector<double>& local, int c, double x)
    {
      const double d = x - mean[c];
      local[c] += d * d;
    },
    [&](const std::vector<double>& local)
    {
      for (int c = 0; c < F; ++c)
      {
        stats.sqdev[c] += local[c];
      }
    });
}

void applyNormalizationCPU(const FeatureOutput& out, const unsigned char* mask,
  const std::vector<double>& offset, const std::vector<double>& scale)
{
  const int F = out.cols;
  const std::int64_t n = static_cast<std::int64_t>(out.rows);
#pragma omp parallel for schedule(static)
  for (std::int64_t r = 0; r < n; ++r)
  {
    float* row = out.data + static_cast<std::size_t>(r) * F;
    if (mask && mask[r])
    {
      std::fill(row, row + F, 0.0f);
      continue;
    }
    for (int c = 0; c < F; ++c)
    {
      const float y = static_cast<float>((static_cast<double>(row[c]) - offset[c]) * scale[c]);
      row[c] = (scale[c] != 0.0 && std::isfinite(y)) ? y : 0.0f;
    }
  }
}

// Offsets and scales from the statistics; constant columns get scale 0.
void normalizationFromStats(FeatureNormalization norm, const ColumnStats& stats,
  FeatureResult& result)
{
  const std::size_t F = stats.count.size();
  result.columnOffset.assign(F, 0.0);
  result.columnScale.assign(F, 1.0);
  result.constantColumns.clear();
  if (norm == FeatureNormalization::None)
  {
    return;
  }
  for (std::size_t c = 0; c < F; ++c)
  {
    const bool constant = !(stats.count[c] > 0) || !(stats.max[c] > stats.min[c]);
    double offset = 0.0, scale = 0.0;
    if (!constant)
    {
      if (norm == FeatureNormalization::ZScore)
      {
        const double sd = std::sqrt(stats.sqdev[c] / stats.count[c]);
        offset = stats.sum[c] / stats.count[c];
        scale = sd > 0.0 && std::isfinite(1.0 / sd) ? 1.0 / sd : 0.0;
      }
      else
      {
        const double range = stats.max[c] - stats.min[c];
        offset = stats.min[c];
        scale = std::isfinite(1.0 / range) ? 1.0 / range : 0.0;
      }
    }
    if (scale == 0.0)
    {
      result.constantColumns.push_back(static_cast<int>(c));
    }
    result.columnOffset[c] = offset;
    result.columnScale[c] = scale;
  }
}

ColumnStats mergeStats(const std::vector<ColumnStats>& parts)
{
  ColumnStats total;
  total.reset(parts.empty() ? 0 : static_cast<int>(parts.front().count.size()));
  for (const ColumnStats& p : parts)
  {
    for (std::size_t c = 0; c < total.count.size(); ++c)
    {
      total.count[c] += p.count[c];
      total.sum[c] += p.sum[c];
      total.min[c] = std::min(total.min[c], p.min[c]);
      total.max[c] = std::max(total.max[c], p.max[c]);
    }
  }
  // Chan's pairwise formula: each part's deviations about its own mean, plus its count
  // times its mean's squared distance to the total mean.
  for (const ColumnStats& p : parts)
  {
    for (std::size_t c = 0; c < total.count.size(); ++c)
    {
      if (p.count[c] > 0)
      {
        const double d = p.sum[c] / p.count[c] - total.sum[c] / total.count[c];
        total.sqdev[c] += p.sqdev[c] + p.count[c] * d * d;
      }
    }
  }
  return total;
}

VolumeStats combineStats(const ColumnStats& local, const std::vector<double>& badPerChannel,
  double badVoxels, double voxels, const Communicator* comm)
{
  VolumeStats total;
  total.ready = true;
  if (!isDistributed(comm))
  {
    total.columns = local;
    total.badPerChannel = badPerChannel;
    total.badVoxels = badVoxels;
    total.voxels = voxels;
    return total;
  }
  const std::size_t F = local.count.size(), C = badPerChannel.size();
  std::vector<double> packed{ voxels, badVoxels };
  packed.insert(packed.end(), badPerChannel.begin(), badPerChannel.end());
  for (const std::vector<double>* column :
    { &local.count, &local.sum, &local.min, &local.max, &local.sqdev })
  {
    packed.insert(packed.end(), column->begin(), column->end());
  }
  const std::vector<double> all = allGatherValues(*comm, packed);
  const std::size_t stride = packed.size();
  total.badPerChannel.assign(C, 0.0);
  std::vector<ColumnStats> parts;
  for (std::size_t r = 0; r * stride < all.size(); ++r)
  {
    const double* p = all.data() + r * stride;
    total.voxels += p[0];
    total.badVoxels += p[1];
    for (std::size_t c = 0; c < C; ++c)
    {
      total.badPerChannel[c] += p[2 + c];
    }
    const double* column = p + 2 + C;
    ColumnStats part;
    for (std::vector<double>* to : { &part.count, &part.sum, &part.min, &part.max, &part.sqdev })
    {
      to->assign(column, column + F);
      column += F;
    }
    parts.push_back(std::move(part));
  }
  total.columns = mergeStats(parts);
  return total;
}

std::size_t overflowCount(const VolumeStats& volume)
{
  std::size_t overflow = 0;
  const double validRows = volume.voxels - volume.badVoxels;
  for (std::size_t c = 0; c < volume.columns.count.size(); ++c)
  {
    overflow += static_cast<std::size_t>(validRows - volume.columns.count[c]);
  }
  return overflow;
}

void addStatsWarnings(const VolumeStats& volume, const FeatureOptions& options, std::size_t overflow,
  FeatureResult& result)
{
  if (volume.badVoxels > 0)
  {
    std::ostringstream os;
    os << result.nonFiniteVoxels << " voxel(s) hold NaN/Inf in some channel (";
    bool first = true;
    for (std::size_t c = 0; c < options.channelNames.size(); ++c)
    {
      if (volume.badPerChannel[c] > 0)
      {
        os << (first ? "" : ", ") << options.channelNames[c] << ": "
           << static_cast<std::size_t>(volume.badPerChannel[c]);
        first = false;
      }
    }
    os << "): their features are 0 and they are left out of the normalisation; as "
          "neighbours they count as the centre voxel's value.";
    result.warnings.push_back(os.str());
  }
  if (overflow > 0)
  {
    // Raw features that overflow float32 (finite input, e.g. values near 1e38): per column.
    std::ostringstream os;
    os << overflow << " feature value(s) overflow float32 and are set to 0 (";
    const double validRows = volume.voxels - volume.badVoxels;
    bool first = true;
    for (std::size_t c = 0; c < volume.columns.count.size(); ++c)
    {
      const auto inColumn = static_cast<std::size_t>(validRows - volume.columns.count[c]);
      if (inColumn > 0)
      {
        os << (first ? "" : ", ") << result.names[c] << ": " << inColumn;
        first = false;
      }
    }
    os << "); the other voxels' normalisation leaves them out. The channel's values are too "
          "large for float32 features: rescale the channel (e.g. a Calculator multiplying "
          "it by 1e-30) and apply again.";
    result.warnings.push_back(os.str());
  }
  if (!result.constantColumns.empty())
  {
    std::ostringstream os;
    os << result.constantColumns.size() << " feature column(s) are constant";
    if (volume.badVoxels == volume.voxels)
    {
      os << " (no voxel is finite in every channel)";
    }
    os << " and are left at 0 under " << normalizationName(options.normalization)
       << " normalisation: ";
    for (std::size_t i = 0; i < result.constantColumns.size(); ++i)
    {
      os << (i ? ", " : "") << result.names[result.constantColumns[i]];
    }
    os << ".";
    result.warnings.push_back(os.str());
  }
}

std::string checkInput(const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const FeatureOptions& options)
{
  if (channels.empty())
  {
    return "no channel: the features need at least one channel";
  }
  if (grid.dims[0] <= 0 || grid.dims[1] <= 0 || grid.dims[2] <= 0)
  {
    return "the input volume is empty (no voxels)";
  }
  if (!grid.spacingProblem().empty())
  {
    return grid.spacingProblem();
  }
  for (std::size_t c = 0; c < channels.size(); ++c)
  {
    const ChannelView& ch = channels[c];
    if (!ch.data || ch.numComponents < 1 || ch.component < 0 || ch.component >= ch.numComponents)
    {
      return "channel " + std::to_string(c + 1) + " has no data or an invalid component (" +
        std::to_string(ch.component) + " of " + std::to_string(ch.numComponents) + ")";
    }
  }
  if (!options.channelNames.empty() && options.channelNames.size() != channels.size())
  {
    return "got " + std::to_string(options.channelNames.size()) + " channel names for " +
      std::to_string(channels.size()) + " channels";
  }
  const FeatureSelection sel = FeatureSelection::forPreset(options.preset, options.custom);
  if (sel.perChannel() == 0)
  {
    return "no feature selected (FeatureSet Custom with every feature turned off)";
  }
  return "";
}

} // namespace detail

namespace
{

using Clock = std::chrono::steady_clock;

void report(const FeatureOptions& options, double fraction)
{
  if (options.progress)
  {
    options.progress(std::min(1.0, std::max(0.0, fraction)));
  }
}


// The steps of the computation on one device; the GPU one throws nothing and reports
// failure through `error`, after which the CPU one redoes everything.
struct CpuBackend
{
  const FeatureOutput& out;
  bool addChannel(const float* values, bool hasNonFinite, const ImageGrid& grid,
    const FeatureSelection& sel, int firstColumn, std::string*)
  {
    detail::channelFeaturesCPU(values, hasNonFinite, grid, sel, out, firstColumn);
    return true;
  }
  bool setMask(const unsigned char*, std::string*) { return true; }
  bool columnStats(
    const unsigned char* mask, bool deviation, detail::ColumnStats& stats, std::string*)
  {
    detail::columnStatsCPU(out, mask, deviation, stats);
    return true;
  }
  bool apply(const unsigned char* mask, const std::vector<double>& offset,
    const std::vector<double>& scale, std::string*)
  {
    detail::applyNormalizationCPU(out, mask, offset, scale);
    return true;
  }
  bool finish(std::string*) { return true; }
};

#ifdef MCV_HAS_CUDA
struct GpuBackend
{
  const FeatureOutput& out;
  cuda::FeatureMatrixGpu gpu;
  bool allocate(std::string* error) { return gpu.allocate(out.rows, out.cols, error); }
  bool addChannel(const float* values, bool hasNonFinite, const ImageGrid& grid,
    const FeatureSelection& sel, int firstColumn, std::string* error)
  {
    return gpu.addChannel(values, hasNonFinite, grid, sel, firstColumn, error);
  }
  bool setMask(const unsigned char* mask, std::string* error) { return gpu.setMask(mask, error); }
  bool columnStats(
    const unsigned char*, bool deviation, detail::ColumnStats& stats, std::string* error)
  {
    return gpu.columnStats(deviation, stats, error);
  }
  bool apply(const unsigned char*, const std::vector<double>& offset,
    const std::vector<double>& scale, std::string* error)
  {
    return gpu.applyNormalization(offset, scale, error);
  }
  bool finish(std::string* error) { return gpu.download(out.data, error); }
};
#endif


// 1 for the voxels of the block this process does not own (ghosts, shared boundary).
std::vector<unsigned char> notOwnedMask(const GridPiece& piece, const ImageGrid& grid)
{
  std::vector<unsigned char> mask(grid.voxelCount());
  std::size_t v = 0;
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i)
        mask[v++] = piece.owns(i, j, k) ? 0 : 1;
  return mask;
}

// Runs every step on `backend`. Returns false (with `error`) only on a backend failure.
template <class Backend>
bool run(Backend& backend, const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const FeatureOptions& options, const FeatureSelection& sel, const FeatureOutput& out,
  detail::VolumeStats& volume, FeatureResult& result, std::string* error)
{
  const std::size_t n = grid.voxelCount();
  const int perChannel = sel.perChannel();
  // Split over processes: only owned voxels count in the statistics and warnings.
  const bool partial = isPartialBlock(options.piece, grid);
  const std::vector<unsigned char> notOwned =
    partial ? notOwnedMask(options.piece, grid) : std::vector<unsigned char>();
  auto countOwned = [&](const std::vector<unsigned char>& m) {
    const std::int64_t count = static_cast<std::int64_t>(n);
    std::size_t b = 0;
#pragma omp parallel for reduction(+ : b)
    for (std::int64_t v = 0; v < count; ++v)
    {
      b += (m[v] && !(partial && notOwned[v])) ? 1 : 0;
    }
    return b;
  };
  std::vector<float> values(n);
  std::vector<unsigned char> mask(n, 0);
  std::vector<unsigned char> channelMask;
  std::vector<double> badPerChannel(channels.size(), 0.0);
  bool anyBad = false;
  const double channelShare = 0.8;
  for (std::size_t c = 0; c < channels.size(); ++c)
  {
    std::size_t bad = 0;
    if (partial)
    {
      channelMask.assign(n, 0);
      bad = detail::channelToFloat(channels[c], n, values.data(), channelMask.data());
      if (bad > 0)
      {
        badPerChannel[c] = static_cast<double>(countOwned(channelMask));
        std::transform(mask.begin(), mask.end(), channelMask.begin(), mask.begin(),
          [](unsigned char a, unsigned char b) { return static_cast<unsigned char>(a | b); });
      }
    }
    else
    {
      bad = detail::channelToFloat(channels[c], n, values.data(), mask.data());
      badPerChannel[c] = static_cast<double>(bad);
    }
    anyBad = anyBad || bad > 0;
    if (!backend.addChannel(
          values.data(), bad > 0, grid, sel, static_cast<int>(c) * perChannel, error))
    {
      return false;
    }
    report(options, channelShare * static_cast<double>(c + 1) / channels.size());
  }
  const unsigned char* maskPtr = anyBad ? mask.data() : nullptr;
  const std::size_t badVoxels = anyBad ? countOwned(mask) : 0;

  // The statistics leave out non-finite voxels and, split over processes, the voxels
  // another process owns.
  std::vector<unsigned char> statsMask;
  if (partial)
  {
    statsMask = notOwned;
    if (anyBad)
    {
      std::transform(statsMask.begin(), statsMask.end(), mask.begin(), statsMask.begin(),
        [](unsigned char a, unsigned char b) { return static_cast<unsigned char>(a | b); });
    }
  }
  const unsigned char* statsMaskPtr = partial ? statsMask.data() : maskPtr;
  if (statsMaskPtr && !backend.setMask(statsMaskPtr, error))
  {
    return false;
  }

  // Statistics: always pass 1 (counts tell of overflowing raw features); pass 2 for ZScore.
  detail::ColumnStats stats;
  if (!backend.columnStats(
        statsMaskPtr, options.normalization == FeatureNormalization::ZScore, stats, error))
  {
    return false;
  }
  if (!volume.ready)
  {
    const double voxels = static_cast<double>(partial ? options.piece.ownedCount() : n);
    volume = detail::combineStats(stats, badPerChannel, static_cast<double>(badVoxels), voxels,
      options.communicator);
  }
  report(options, 0.9);
  detail::normalizationFromStats(options.normalization, volume.columns, result);
  result.nonFiniteVoxels = static_cast<std::size_t>(volume.badVoxels);
  const std::size_t overflow = detail::overflowCount(volume);
  // The output is zeroed on non-finite voxels only (ghost and shared voxels get values).
  if (partial && !backend.setMask(maskPtr, error))
  {
    return false;
  }
  if (options.normalization != FeatureNormalization::None || anyBad || overflow > 0)
  {
    if (!backend.apply(maskPtr, result.columnOffset, result.columnScale, error))
    {
      return false;
    }
  }
  if (!backend.finish(error))
  {
    return false;
  }

  // Warnings (only once the device has succeeded, so a fallback does not repeat them).
  detail::addStatsWarnings(volume, options, overflow, result);
  return true;
}

} // namespace

namespace
{
// The argument checks of computeFeatures; "" when the arguments are usable.
std::string checkArguments(const std::vector<ChannelView>& channels, const ImageGrid& grid,
  const FeatureOptions& options, const FeatureOutput& out)
{
  const std::string error = detail::checkInput(channels, grid, options);
  if (!error.empty())
  {
    return error;
  }
  const int F = featureCount(channels.size(), options);
  const std::size_t n = grid.voxelCount();
  if (!out.data || out.rows != n || out.cols != F)
  {
    return "the output buffer is " + std::to_string(out.rows) + " x " +
      std::to_string(out.cols) + ", expected " + std::to_string(n) + " x " + std::to_string(F);
  }
  return "";
}
} // namespace

bool computeFeatures(const std::vector<ChannelView>& channelsIn, const ImageGrid& grid,
  const FeatureOptions& optionsIn, const FeatureOutput& out, FeatureResult& result)
{
  const auto start = Clock::now();
  result = FeatureResult();
  // Split over processes, every process takes the same branch: one with bad arguments
  // stops all of them (the others would wait in the statistics exchange).
  result.error = checkArguments(channelsIn, grid, optionsIn, out);
  if (!allTrue(optionsIn.communicator, result.error.empty()))
  {
    if (result.error.empty())
    {
      result.error = "another process of the parallel run reported an error";
    }
    return false;
  }
  const std::vector<ChannelView>& channels = channelsIn;
  FeatureOptions options = optionsIn;
  if (options.channelNames.empty())
  {
    for (std::size_t c = 0; c < channels.size(); ++c)
    {
      options.channelNames.push_back("ch" + std::to_string(c + 1));
    }
  }
  const FeatureSelection sel = FeatureSelection::forPreset(options.preset, options.custom);
  result.names = featureNames(options.channelNames, sel);
  report(options, 0.0);

  std::string warning;
  result.deviceUsed = resolveDevice(options.device, &warning);
  if (!warning.empty())
  {
    result.warnings.push_back(warning);
  }
  std::string error;
  detail::VolumeStats volume;
#ifdef MCV_HAS_CUDA
  if (result.deviceUsed == Device::GPU)
  {
    GpuBackend gpu{ out, {} };
    const std::vector<std::string> keep = result.warnings;
    if (gpu.allocate(&error) &&
      run(gpu, channels, grid, options, sel, out, volume, result, &error))
    {
      result.totalMs =
        std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      report(options, 1.0);
      return true;
    }
    result.warnings = keep;
    result.warnings.push_back("GPU path failed (" + error + "); running on the CPU.");
    result.deviceUsed = Device::CPU;
  }
#else
  result.deviceUsed = Device::CPU;
#endif
  // Serial: the CPU recomputes the statistics too, so the result is the CPU path's to the
  // last bit. Split over processes the exchanged statistics are kept (a second exchange
  // would leave the other processes waiting).
  if (!isDistributed(options.communicator))
  {
    volume = detail::VolumeStats();
  }
  CpuBackend cpu{ out };
  run(cpu, channels, grid, options, sel, out, volume, result, &error);
  result.totalMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  report(options, 1.0);
  return true;
}

} // namespace mcv
