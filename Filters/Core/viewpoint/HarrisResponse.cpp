#include "HarrisResponse.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

// The CPU path works on tiles of the volume: a run of whole x rows (or of 256 columns of
// wider volumes) by tileY rows, streamed along z. For each z-slice, the six gradient
// products of one row are formed and smoothed along x at once; the rows of the tile (plus
// the y halo) are smoothed along y into a ring of KernelWidth slices; the z pass reads the
// ring and forms the response row by row. The ring of a tile stays in the core's L2 cache
// (about 0.5 MB), so after the input is read once nothing leaves the cache but the
// responses; every loop runs along contiguous x and vectorises (AVX2 with FMA where the
// CPU has it, chosen at run time). Written by hand because VTK-free libraries offer no
// fused, border-replicating separable 3D filter over six channels.
//
// Rounding follows the CUDA kernel: every Gaussian pass is a chain of fused multiply-adds
// from 0 in tap order, the gradients and products are the same expressions, and the
// response is fused where the kernel's machine code fuses it (HarrisTileKernels.h,
// harrisFromTensor). This file is compiled with -ffp-contract=off, so only the written fma
// calls fuse.

#if defined(__GNUC__) || defined(__clang__)
#define MCV_HARRIS_INLINE inline __attribute__((always_inline))
#define MCV_HARRIS_LAMBDA_INLINE __attribute__((always_inline))
#else
#define MCV_HARRIS_INLINE inline
#define MCV_HARRIS_LAMBDA_INLINE
#endif
// GCC compiles a second copy of the kernels for AVX2 + FMA (#pragma GCC target).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define MCV_HARRIS_X86 1
#include <immintrin.h>
#endif

namespace mcv
{

void gaussianTaps(const HarrisParameters& params, float* taps)
{
  const int width = params.kernelWidth;
  const int radius = width / 2;
  double sum = 0.0;
  std::vector<double> w(static_cast<std::size_t>(width));
  for (int t = 0; t < width; ++t)
  {
    const double d = t - radius;
    w[t] = std::exp(-d * d / (2.0 * params.sigma * params.sigma));
    sum += w[t];
  }
  for (int t = 0; t < width; ++t)
  {
    taps[t] = static_cast<float>(w[t] / sum);
  }
}

const char* checkHarrisParameters(const HarrisParameters& params)
{
  if (!(params.sigma > 0.0) || !std::isfinite(params.sigma))
  {
    return "GaussianSigma must be a positive, finite number of voxels (the default is 1.5)";
  }
  if (params.kernelWidth < 1 || params.kernelWidth % 2 == 0 || params.kernelWidth > 31)
  {
    return "KernelWidth must be odd, between 1 and 31 taps (the default is 5)";
  }
  if (!std::isfinite(params.k) || params.k < 0.0)
  {
    return "HarrisK must be a finite number >= 0 (the default is 0.004)";
  }
  return "";
}

namespace
{

constexpr int Channels = 6; // xx, xy, xz, yy, yz, zz
constexpr int kMaxWidth = 31;
// Widest tile along x: wider rows are cut into tiles of at most this many columns.
constexpr int kMaxTileX = 384;
// Bytes of a tile's ring of y-smoothed slices, to stay within a core's L2 cache.
constexpr std::size_t kTileBytes = 640 * 1024;

inline int clampIndex(int i, int n)
{
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

struct Setup
{
  const float* opacity = nullptr;
  int nx = 0, ny = 0, nz = 0;
  int width = 0, radius = 0;
  float taps[kMaxWidth] = {};
  float scale[3] = { 0, 0, 0 }; // 0.5 / spacing
  float k = 0;
  int plane = -1; // < 0: 3D form; else the axis of size 1 (2D form on the other two)
  int tileX = 0, tileY = 0;
};

struct Tile
{
  int x0, x1, y0, y1, z0, z1; // output voxels [x0, x1) x [y0, y1) x [z0, z1)
};

// One thread's working memory, sized for the largest tile.
struct Scratch
{
  explicit Scratch(const Setup& s)
    : products(static_cast<std::size_t>(Channels) * (s.tileX + 2 * s.radius))
    , xSmoothed(static_cast<std::size_t>(s.width) * Channels * s.tileX)
    , ring(static_cast<std::size_t>(s.width + 1) * s.tileY * Channels * s.tileX)
    , ringSlice(static_cast<std::size_t>(s.width + 1), -1)
    , tensor(static_cast<std::size_t>(2) * Channels * s.tileX)
    , row(static_cast<std::size_t>(s.tileX))
  {
  }
  std::vector<float> products;  // [channel][tileX + 2 radius]: one row, x halo included
  std::vector<float> xSmoothed; // [row % width][channel][tileX]: x-smoothed rows
  std::vector<float> ring;      // [slice % (width + 1)][row of tile][channel][tileX]
  std::vector<int> ringSlice;   // the z-slice each slot holds (-1: none)
  std::vector<float> tensor;    // [slice of the pair][channel][tileX]: one row, smoothed
  std::vector<float> row;       // one row of responses (when they are not kept)
};

// Writes the responses into the whole response volume.
struct VolumeSink
{
  float* response;
  std::size_t nx, plane;
  int x0;
  float* row(int z, int j) const { return response + z * plane + j * nx + x0; }
  void done(int, int, const float*) const {}
};

// Offers the responses of the candidate voxels to a collector.
struct CollectSink
{
  TopResponseCollector* collector;
  float* scratchRow;
  std::int64_t nx, plane;
  int x0, x1;
  VoxelBox box;
  float* row(int, int) const { return scratchRow; }
  void done(int z, int j, const float* values) const
  {
    if (z < box.lo[2] || z > box.hi[2] || j < box.lo[1] || j > box.hi[1])
    {
      return;
    }
    const int a = std::max(x0, box.lo[0]), b = std::min(x1 - 1, box.hi[0]);
    if (a <= b)
    {
      collector->offer(values + (a - x0), z * plane + j * nx + a, static_cast<std::size_t>(b - a + 1));
    }
  }
};

// The tile kernels, portable: Pack is one float.
namespace portable
{
using Pack = float;
constexpr int kLanes = 1;
template <class P>
MCV_HARRIS_INLINE P load(const float* p)
{
  return *p;
}
template <class P>
MCV_HARRIS_INLINE P splat(float x)
{
  return x;
}
MCV_HARRIS_INLINE void store(float* p, float v)
{
  *p = v;
}
MCV_HARRIS_INLINE float fmadd(float a, float b, float c)
{
  return std::fma(a, b, c);
}
MCV_HARRIS_INLINE float negate(float a)
{
  return -a;
}
#include "HarrisTileKernels.h"
} // namespace portable

#ifdef MCV_HARRIS_X86
// The same kernels for AVX2 with FMA, eight floats a time (the scalar tails use the FMA
// instruction too, so they round exactly as the portable build's std::fma).
#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace avx2
{
struct Pack
{
  __m256 v;
};
constexpr int kLanes = 8;
MCV_HARRIS_INLINE Pack operator+(Pack a, Pack b)
{
  return { _mm256_add_ps(a.v, b.v) };
}
MCV_HARRIS_INLINE Pack operator-(Pack a, Pack b)
{
  return { _mm256_sub_ps(a.v, b.v) };
}
MCV_HARRIS_INLINE Pack operator*(Pack a, Pack b)
{
  return { _mm256_mul_ps(a.v, b.v) };
}
template <class P>
MCV_HARRIS_INLINE P load(const float* p);
template <>
MCV_HARRIS_INLINE float load<float>(const float* p)
{
  return *p;
}
template <>
MCV_HARRIS_INLINE Pack load<Pack>(const float* p)
{
  return { _mm256_loadu_ps(p) };
}
template <class P>
MCV_HARRIS_INLINE P splat(float x);
template <>
MCV_HARRIS_INLINE float splat<float>(float x)
{
  return x;
}
template <>
MCV_HARRIS_INLINE Pack splat<Pack>(float x)
{
  return { _mm256_set1_ps(x) };
}
MCV_HARRIS_INLINE void store(float* p, float v)
{
  *p = v;
}
MCV_HARRIS_INLINE void store(float* p, Pack v)
{
  _mm256_storeu_ps(p, v.v);
}
MCV_HARRIS_INLINE float fmadd(float a, float b, float c)
{
  return std::fma(a, b, c);
}
MCV_HARRIS_INLINE Pack fmadd(Pack a, Pack b, Pack c)
{
  return { _mm256_fmadd_ps(a.v, b.v, c.v) };
}
MCV_HARRIS_INLINE float negate(float a)
{
  return -a;
}
MCV_HARRIS_INLINE Pack negate(Pack a)
{
  return { _mm256_xor_ps(a.v, _mm256_set1_ps(-0.f)) };
}
#include "HarrisTileKernels.h"
} // namespace avx2
#pragma GCC pop_options

bool hasAvx2Fma()
{
  static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return ok;
}
#endif

// The tile function for this CPU and kernel width (the common widths unrolled).
template <class Sink>
using TileFn = void (*)(const Setup&, const Tile&, Scratch&, Sink&);

template <class Sink, int W>
TileFn<Sink> tileFunctionFor(HarrisCpuKernel kernel)
{
#ifdef MCV_HARRIS_X86
  if (kernel == HarrisCpuKernel::Auto && hasAvx2Fma())
  {
    return &avx2::runTile<W, Sink>;
  }
#else
  (void)kernel;
#endif
  return &portable::runTile<W, Sink>;
}

template <class Sink>
TileFn<Sink> tileFunction(int width, HarrisCpuKernel kernel)
{
  switch (width)
  {
    case 3:
      return tileFunctionFor<Sink, 3>(kernel);
    case 5:
      return tileFunctionFor<Sink, 5>(kernel);
    case 7:
      return tileFunctionFor<Sink, 7>(kernel);
    default:
      return tileFunctionFor<Sink, 0>(kernel);
  }
}

Setup makeSetup(const float* opacity, const ImageGrid& grid, const HarrisParameters& params)
{
  Setup s;
  s.opacity = opacity;
  s.nx = grid.dims[0];
  s.ny = grid.dims[1];
  s.nz = grid.dims[2];
  s.width = params.kernelWidth;
  s.radius = params.kernelWidth / 2;
  gaussianTaps(params, s.taps);
  for (int a = 0; a < 3; ++a)
  {
    s.scale[a] = static_cast<float>(0.5 / grid.spacing[a]);
  }
  s.k = static_cast<float>(params.k);
  if (grid.extendedAxes() == 2)
  {
    s.plane = s.nx == 1 ? 0 : (s.ny == 1 ? 1 : 2);
  }
  // Tiles: whole rows up to kMaxTileX columns (else near-equal parts of at most 256), and
  // as many rows as keep the ring of width + 1 slices within kTileBytes.
  const int xTiles = s.nx <= kMaxTileX ? 1 : (s.nx + 255) / 256;
  s.tileX = (s.nx + xTiles - 1) / xTiles;
  const std::size_t rowBytes = sizeof(float) * Channels * static_cast<std::size_t>(s.tileX) * (s.width + 1);
  const int fit = std::max(4, static_cast<int>(kTileBytes / rowBytes));
  const int yTiles = (s.ny + fit - 1) / fit; // then rows shared out evenly among them
  s.tileY = std::max(1, (s.ny + yTiles - 1) / yTiles);
  return s;
}

// Every tile of the volume, in z chunks when there are too few tiles to keep every thread
// busy (a chunk recomputes 2 radius halo slices).
std::vector<Tile> makeTiles(const Setup& s, int threads)
{
  const int xTiles = (s.nx + s.tileX - 1) / s.tileX;
  const int yTiles = (s.ny + s.tileY - 1) / s.tileY;
  const int planeTiles = xTiles * yTiles;
  int zChunks = 1;
  if (planeTiles < 4 * threads)
  {
    zChunks = std::max(1, std::min((4 * threads + planeTiles - 1) / planeTiles, s.nz / (4 * s.width)));
  }
  std::vector<Tile> tiles;
  tiles.reserve(static_cast<std::size_t>(planeTiles) * zChunks);
  for (int c = 0; c < zChunks; ++c)
  {
    const int z0 = static_cast<int>(static_cast<std::int64_t>(s.nz) * c / zChunks);
    const int z1 = static_cast<int>(static_cast<std::int64_t>(s.nz) * (c + 1) / zChunks);
    for (int ty = 0; ty < yTiles; ++ty)
    {
      for (int tx = 0; tx < xTiles; ++tx)
      {
        const int x0 = static_cast<int>(static_cast<std::int64_t>(s.nx) * tx / xTiles);
        const int x1 = static_cast<int>(static_cast<std::int64_t>(s.nx) * (tx + 1) / xTiles);
        const int y0 = ty * s.tileY, y1 = std::min(s.ny, y0 + s.tileY);
        tiles.push_back(Tile{ x0, x1, y0, y1, z0, z1 });
      }
    }
  }
  return tiles;
}

} // namespace

void computeHarrisResponseCPU(const float* opacity, const ImageGrid& grid,
  const HarrisParameters& params, float* response, HarrisCpuKernel kernel)
{
  const Setup s = makeSetup(opacity, grid, params);
  const std::vector<Tile> tiles = makeTiles(s, omp_get_max_threads());
  const TileFn<VolumeSink> run = tileFunction<VolumeSink>(s.width, kernel);
  const long long count = static_cast<long long>(tiles.size());
#pragma omp parallel
  {
    Scratch scratch(s);
#pragma omp for schedule(dynamic, 1)
    for (long long i = 0; i < count; ++i)
    {
      const Tile& t = tiles[static_cast<std::size_t>(i)];
      VolumeSink sink{ response, static_cast<std::size_t>(s.nx),
        static_cast<std::size_t>(s.nx) * static_cast<std::size_t>(s.ny), t.x0 };
      run(s, t, scratch, sink);
    }
  }
}

InterestPoints computeHarrisTopNCPU(const float* opacity, const ImageGrid& grid,
  const HarrisParameters& params, int N, const VoxelBox* candidates)
{
  if (N <= 0)
  {
    return InterestPoints();
  }
  const Setup s = makeSetup(opacity, grid, params);
  const std::vector<Tile> tiles = makeTiles(s, omp_get_max_threads());
  const TileFn<CollectSink> run = tileFunction<CollectSink>(s.width, HarrisCpuKernel::Auto);
  VoxelBox box;
  for (int a = 0; a < 3; ++a)
  {
    box.hi[a] = grid.dims[a] - 1;
  }
  if (candidates)
  {
    box = *candidates;
  }
  const long long count = static_cast<long long>(tiles.size());
  std::vector<TopResponseCollector> collectors;
#pragma omp parallel
  {
#pragma omp single
    collectors.assign(static_cast<std::size_t>(omp_get_num_threads()),
      TopResponseCollector(static_cast<std::size_t>(N)));
    Scratch scratch(s);
    TopResponseCollector& mine = collectors[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 1)
    for (long long i = 0; i < count; ++i)
    {
      const Tile& t = tiles[static_cast<std::size_t>(i)];
      CollectSink sink{ &mine, scratch.row.data(), s.nx,
        static_cast<std::int64_t>(s.nx) * s.ny, t.x0, t.x1, box };
      run(s, t, scratch, sink);
    }
  }
  return mergeCollectors(collectors, N);
}

} // namespace mcv
