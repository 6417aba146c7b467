// Test volumes for the core unit tests, the GPU tests and the benchmarks. VTK-free and
// header-only: real volumes (NIfTI-1, VolPack .den) fetched by scripts/fetch-data.sh, and
// synthetic volumes whose answer is known.
//
// Linking: the NIfTI loader reads through zlib (gzopen/gzread also read uncompressed .nii
// files), so a target that calls loadNifti() must link zlib:
//     find_package(ZLIB REQUIRED)
//     target_link_libraries(<target> PRIVATE ZLIB::ZLIB)
// Targets that only use the synthetic makers or loadVolPackDen() need nothing (the inline
// functions that call zlib are then never emitted). Where zlib is missing, define
// MCV_TESTVOLUMES_NO_ZLIB: loadNifti() then reads plain .nii only (.nii.gz throws).
//
// Errors: the loaders throw std::runtime_error with a message that names the file and
// what is wrong with it. Tests use dataFile()/haveDataFile() to skip missing volumes.
#pragma once

#include "ImageGrid.h"

#ifndef MCV_TESTVOLUMES_NO_ZLIB
#include <zlib.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace mcv
{
namespace testing
{

struct Volume
{
  ImageGrid grid;
  std::vector<float> values; // grid.voxelCount() values, x fastest
  std::string name;          // file name or a description of the synthetic volume

  float minValue() const
  {
    float m = std::numeric_limits<float>::infinity();
    for (float v : values)
      if (std::isfinite(v))
        m = std::min(m, v);
    return m;
  }
  float maxValue() const
  {
    float m = -std::numeric_limits<float>::infinity();
    for (float v : values)
      if (std::isfinite(v))
        m = std::max(m, v);
    return m;
  }
};

// ---------------------------------------------------------------------------------------
// Where the real volumes are
// ---------------------------------------------------------------------------------------

// The folder of the real volumes: the MCV_DATA_DIR compile definition (the CMake cache
// variable of the same name) when it names an existing folder, else the environment
// variable MCV_DATA_DIR (a build copied to another machine), else the compile definition
// as it is (or "" without one). Missing files make tests skip, not fail.
inline std::string dataDir()
{
  std::string compiled;
#ifdef MCV_DATA_DIR
  compiled = MCV_DATA_DIR;
#endif
  std::error_code ec;
  if (!compiled.empty() && std::filesystem::is_directory(compiled, ec))
    return compiled;
  const char* env = std::getenv("MCV_DATA_DIR");
  if (env && *env)
    return std::string(env);
  return compiled;
}

// dataDir() + "/" + name.
inline std::string dataFile(const std::string& name)
{
  const std::string dir = dataDir();
  return dir.empty() ? name : dir + "/" + name;
}

inline bool haveDataFile(const std::string& name)
{
  std::ifstream f(dataFile(name), std::ios::binary);
  return f.good();
}

// ---------------------------------------------------------------------------------------
// NIfTI-1 (.nii, .nii.gz)
// ---------------------------------------------------------------------------------------

namespace detail
{
inline void swap2(void* p)
{
  auto* b = static_cast<unsigned char*>(p);
  std::swap(b[0], b[1]);
}
inline void swap4(void* p)
{
  auto* b = static_cast<unsigned char*>(p);
  std::swap(b[0], b[3]);
  std::swap(b[1], b[2]);
}
inline void swap8(void* p)
{
  auto* b = static_cast<unsigned char*>(p);
  for (int i = 0; i < 4; ++i)
    std::swap(b[i], b[7 - i]);
}
inline void swapN(void* p, int bytes)
{
  if (bytes == 2)
    swap2(p);
  else if (bytes == 4)
    swap4(p);
  else if (bytes == 8)
    swap8(p);
}

struct NiftiInfo
{
  std::array<int, 3> dims{ 1, 1, 1 };
  std::array<double, 3> spacing{ 1, 1, 1 };
  std::int64_t volumes = 1; // product of dim[4..7]
  int datatype = 0;
  int bytesPerVoxel = 0;
  std::int64_t voxOffset = 352;
  double slope = 1.0, inter = 0.0;
  bool swapped = false;
};

// Sequential reader of a possibly gzip-compressed file: zlib's gzread (which reads plain
// files too), or, built with MCV_TESTVOLUMES_NO_ZLIB, std::ifstream for plain files only.
class ByteReader
{
public:
  explicit ByteReader(const std::string& path) : path_(path)
  {
#ifndef MCV_TESTVOLUMES_NO_ZLIB
    f_ = gzopen(path.c_str(), "rb");
    if (!f_)
      throw std::runtime_error(path + ": cannot open (run scripts/fetch-data.sh?)");
#else
    const bool gz = path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
    if (gz)
      throw std::runtime_error(path + ": this build has no zlib (MCV_TESTVOLUMES_NO_ZLIB): "
                                      "cannot read gzip-compressed files");
    in_.open(path, std::ios::binary);
    if (!in_)
      throw std::runtime_error(path + ": cannot open (run scripts/fetch-data.sh?)");
#endif
  }
  ~ByteReader()
  {
#ifndef MCV_TESTVOLUMES_NO_ZLIB
    if (f_)
      gzclose(f_);
#endif
  }
  ByteReader(const ByteReader&) = delete;
  ByteReader& operator=(const ByteReader&) = delete;

  // Reads exactly `bytes` bytes or throws.
  void read(void* dst, std::size_t bytes)
  {
    auto* out = static_cast<unsigned char*>(dst);
    while (bytes > 0)
    {
      const unsigned chunk = static_cast<unsigned>(std::min<std::size_t>(bytes, 1u << 30));
#ifndef MCV_TESTVOLUMES_NO_ZLIB
      const int got = gzread(f_, out, chunk);
      if (got <= 0)
      {
        int err = Z_OK;
        const char* msg = gzerror(f_, &err);
        throw std::runtime_error(path_ + ": truncated or unreadable (" +
          (err != Z_OK && msg ? std::string(msg) : std::string("unexpected end of file")) + ")");
      }
#else
      in_.read(reinterpret_cast<char*>(out), chunk);
      const std::streamsize got = in_.gcount();
      if (got <= 0)
        throw std::runtime_error(path_ + ": truncated (unexpected end of file)");
#endif
      out += got;
      bytes -= static_cast<std::size_t>(got);
    }
  }

  void skip(std::int64_t bytes)
  {
    std::vector<unsigned char> sink(1 << 16);
    while (bytes > 0)
    {
      const std::size_t n = static_cast<std::size_t>(std::min<std::int64_t>(bytes, sink.size()));
      read(sink.data(), n);
      bytes -= static_cast<std::int64_t>(n);
    }
  }

private:
  std::string path_;
#ifndef MCV_TESTVOLUMES_NO_ZLIB
  gzFile f_ = nullptr;
#else
  std::ifstream in_;
#endif
};

// The NIfTI datatype codes this loader reads and the C++ type each stores, in the same order:
// uint8, int8, int16, uint16, int32, uint32, float32, float64.
constexpr int kNiftiCodes[] = { 2, 256, 4, 512, 8, 768, 16, 64 };
using NiftiStoredTypes =
  std::tuple<std::uint8_t, std::int8_t, std::int16_t, std::uint16_t, std::int32_t, std::uint32_t, float, double>;

template <class F, std::size_t... I>
bool visitNiftiType(int datatype, F& f, std::index_sequence<I...>)
{
  return ((datatype == kNiftiCodes[I] && (f(std::tuple_element_t<I, NiftiStoredTypes>()), true)) || ...);
}

// Calls f(T()) with the C++ type that NIfTI datatype code `datatype` stores; false, without
// calling f, for a code not in kNiftiCodes. The header reader (bytes per voxel) and
// convertVoxel (the value) share this one table.
template <class F>
bool visitNiftiType(int datatype, F&& f)
{
  return visitNiftiType(datatype, f, std::make_index_sequence<std::size(kNiftiCodes)>());
}

inline NiftiInfo readNiftiHeader(ByteReader& f, const std::string& path)
{
  unsigned char h[348];
  f.read(h, sizeof(h));
  auto i32 = [&](int off) {
    std::int32_t v;
    std::memcpy(&v, h + off, 4);
    return v;
  };
  NiftiInfo info;
  std::int32_t sizeofHdr = i32(0);
  if (sizeofHdr != 348)
  {
    swap4(&sizeofHdr);
    if (sizeofHdr != 348)
      throw std::runtime_error(path + ": not a NIfTI-1 file (sizeof_hdr is not 348)");
    info.swapped = true;
  }
  if (!(std::memcmp(h + 344, "n+1", 4) == 0 || std::memcmp(h + 344, "ni1", 4) == 0))
    throw std::runtime_error(path + ": not a NIfTI-1 file (magic is not n+1 or ni1)");
  if (std::memcmp(h + 344, "ni1", 4) == 0)
    throw std::runtime_error(path + ": NIfTI-1 pair (.hdr/.img) files are not supported");

  auto i16 = [&](int off) {
    std::int16_t v;
    std::memcpy(&v, h + off, 2);
    if (info.swapped)
      swap2(&v);
    return v;
  };
  auto f32 = [&](int off) {
    float v;
    std::memcpy(&v, h + off, 4);
    if (info.swapped)
      swap4(&v);
    return v;
  };

  std::int16_t dim[8];
  for (int i = 0; i < 8; ++i)
    dim[i] = i16(40 + 2 * i);
  if (dim[0] < 1 || dim[0] > 7)
    throw std::runtime_error(path + ": bad dim[0] " + std::to_string(dim[0]));
  for (int i = 1; i <= dim[0]; ++i)
    if (dim[i] < 1)
      throw std::runtime_error(path + ": bad dim[" + std::to_string(i) + "] " +
        std::to_string(dim[i]));
  for (int a = 0; a < 3; ++a)
  {
    info.dims[a] = a + 1 <= dim[0] ? dim[a + 1] : 1;
    const double p = a + 1 <= dim[0] ? std::fabs(f32(76 + 4 * (a + 1))) : 1.0;
    info.spacing[a] = (std::isfinite(p) && p > 0) ? p : 1.0;
  }
  info.volumes = 1;
  for (int i = 4; i <= dim[0]; ++i)
    info.volumes *= dim[i];

  info.datatype = i16(70);
  if (!visitNiftiType(info.datatype, [&](auto stored) { info.bytesPerVoxel = sizeof(stored); }))
    throw std::runtime_error(path + ": unsupported NIfTI datatype " +
      std::to_string(info.datatype) +
      " (supported: uint8, int8, int16, uint16, int32, uint32, float32, float64)");
  const float off = f32(108);
  info.voxOffset = (std::isfinite(off) && off >= 348) ? static_cast<std::int64_t>(off) : 352;
  const float slope = f32(112), inter = f32(116);
  if (std::isfinite(slope) && slope != 0.0f && std::isfinite(inter))
  {
    info.slope = slope;
    info.inter = inter;
  }
  return info;
}

// The value of type T stored in the first sizeof(T) bytes of b (host order).
template <class T>
double storedValue(const unsigned char* b)
{
  T x;
  std::memcpy(&x, b, sizeof(T));
  return static_cast<double>(x);
}

inline float convertVoxel(const unsigned char* p, const NiftiInfo& info)
{
  unsigned char b[8];
  std::memcpy(b, p, info.bytesPerVoxel);
  if (info.swapped)
    swapN(b, info.bytesPerVoxel);
  double v = 0;
  visitNiftiType(info.datatype, [&](auto stored) { v = storedValue<decltype(stored)>(b); });
  return static_cast<float>(v * info.slope + info.inter);
}

} // namespace detail

// Number of 3D volumes in a NIfTI-1 file (product of dim[4..7]; 1 for a 3D file).
inline std::int64_t niftiVolumeCount(const std::string& path)
{
  detail::ByteReader f(path);
  return detail::readNiftiHeader(f, path).volumes;
}

// Volumes [first, first + count) of a NIfTI-1 file (.nii or .nii.gz, single file "n+1").
// Grid: dims from dim[1..3], spacing |pixdim[1..3]| (1 where missing or invalid), origin
// (0,0,0); the voxels are kept in file order (the qform/sform orientation is not applied).
// Values: scl_slope/scl_inter applied when scl_slope is non-zero.
inline std::vector<Volume> loadNiftiVolumes(
  const std::string& path, std::int64_t first, std::int64_t count)
{
  detail::ByteReader f(path);
  const detail::NiftiInfo info = detail::readNiftiHeader(f, path);
  if (first < 0 || count < 0 || first + count > info.volumes)
    throw std::runtime_error(path + ": volume range [" + std::to_string(first) + ", " +
      std::to_string(first + count) + ") is outside the file's " +
      std::to_string(info.volumes) + " volume(s)");
  ImageGrid grid;
  grid.dims = info.dims;
  grid.spacing = info.spacing;
  const std::size_t n = grid.voxelCount();
  const std::size_t volBytes = n * static_cast<std::size_t>(info.bytesPerVoxel);
  f.skip(info.voxOffset - 348 + static_cast<std::int64_t>(volBytes) * first);

  std::vector<Volume> out;
  out.reserve(static_cast<std::size_t>(count));
  std::vector<unsigned char> raw(volBytes);
  std::string base = path.substr(path.find_last_of('/') == std::string::npos
      ? 0
      : path.find_last_of('/') + 1);
  for (std::int64_t v = 0; v < count; ++v)
  {
    f.read(raw.data(), volBytes);
    Volume vol;
    vol.grid = grid;
    vol.name = info.volumes > 1 ? base + "[" + std::to_string(first + v) + "]" : base;
    vol.values.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      vol.values[i] = detail::convertVoxel(raw.data() + i * info.bytesPerVoxel, info);
    out.push_back(std::move(vol));
  }
  return out;
}

// One 3D volume of a NIfTI-1 file: the first (volumeIndex 0) for a 4D file.
inline Volume loadNifti(const std::string& path, std::int64_t volumeIndex = 0)
{
  return std::move(loadNiftiVolumes(path, volumeIndex, 1).front());
}

// ---------------------------------------------------------------------------------------
// VolPack .den (brainsmall.den)
// ---------------------------------------------------------------------------------------

// Header layout (VolPack's examples/denfile.c): all shorts in the writer's byte order,
//   short map_version            1 (0x0100 when byte-swapped: tells the byte order)
//   short orig_min[3], orig_max[3], orig_len[3]   the original scan
//   short extr_min[3], extr_max[3], extr_len[3]   the extracted part of it
//   short map_min[3],  map_max[3],  map_len[3]    this map (x, y, z sizes in map_len)
//   short map_warps
//   int   map_length             = map_len[0] * map_len[1] * map_len[2]
// then map_length uint8 densities, x fastest: 62 bytes of header in all.
// Spacing: the format stores none; it is (1,1,1) unless `physicalAspect`, in which case
// it is extr_len / map_len (the resampling factor from the original scan, in original
// voxels; brainsmall.den: 2, 2, 1.298), origin (0,0,0). Values are the bytes 0..255.
inline Volume loadVolPackDen(const std::string& path, bool physicalAspect = false)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error(path + ": cannot open (run scripts/fetch-data.sh?)");
  unsigned char h[62];
  if (!in.read(reinterpret_cast<char*>(h), sizeof(h)))
    throw std::runtime_error(path + ": too short for a VolPack .den header (62 bytes)");
  auto s16 = [&](int off, bool swap) {
    std::int16_t v;
    std::memcpy(&v, h + off, 2);
    if (swap)
      detail::swap2(&v);
    return v;
  };
  bool swap = false;
  const std::int16_t version = s16(0, false);
  if (version == 1)
    swap = false;
  else if (version == 0x0100)
    swap = true;
  else
    throw std::runtime_error(path + ": not a VolPack density (.den) file (map_version " +
      std::to_string(version) + ")");
  // shorts: version(0), orig_min(2), orig_max(8), orig_len(14), extr_min(20), extr_max(26),
  // extr_len(32), map_min(38), map_max(44), map_len(50), map_warps(56), map_length int(58)
  std::array<int, 3> mapLen{}, extrLen{};
  for (int a = 0; a < 3; ++a)
  {
    mapLen[a] = s16(50 + 2 * a, swap);
    extrLen[a] = s16(32 + 2 * a, swap);
    if (mapLen[a] < 1)
      throw std::runtime_error(path + ": bad map_len[" + std::to_string(a) + "] " +
        std::to_string(mapLen[a]));
  }
  std::int32_t length;
  std::memcpy(&length, h + 58, 4);
  if (swap)
    detail::swap4(&length);
  const std::int64_t expected = static_cast<std::int64_t>(mapLen[0]) * mapLen[1] * mapLen[2];
  if (length != expected)
    throw std::runtime_error(path + ": inconsistent header (map_length " +
      std::to_string(length) + " != " + std::to_string(expected) + ")");
  std::vector<unsigned char> raw(static_cast<std::size_t>(expected));
  if (!in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size())))
    throw std::runtime_error(path + ": truncated (" + std::to_string(expected) +
      " density bytes expected)");
  Volume vol;
  vol.grid.dims = mapLen;
  if (physicalAspect)
    for (int a = 0; a < 3; ++a)
      vol.grid.spacing[a] = extrLen[a] > 0 ? static_cast<double>(extrLen[a]) / mapLen[a] : 1.0;
  vol.values.assign(raw.begin(), raw.end());
  vol.name = path.substr(path.find_last_of('/') == std::string::npos
      ? 0
      : path.find_last_of('/') + 1);
  return vol;
}

// ---------------------------------------------------------------------------------------
// Synthetic volumes (known answers)
// ---------------------------------------------------------------------------------------

inline ImageGrid makeGrid(int nx, int ny, int nz, std::array<double, 3> spacing = { 1, 1, 1 },
  std::array<double, 3> origin = { 0, 0, 0 })
{
  ImageGrid g;
  g.dims = { nx, ny, nz };
  g.spacing = spacing;
  g.origin = origin;
  return g;
}

inline Volume constantVolume(const ImageGrid& grid, float value)
{
  Volume v;
  v.grid = grid;
  v.values.assign(grid.voxelCount(), value);
  v.name = "constant";
  return v;
}

// Centre of the grid in world coordinates (the middle of the voxel-centre bounds).
inline std::array<double, 3> gridCenter(const ImageGrid& g)
{
  return { g.origin[0] + 0.5 * g.spacing[0] * (g.dims[0] - 1),
    g.origin[1] + 0.5 * g.spacing[1] * (g.dims[1] - 1),
    g.origin[2] + 0.5 * g.spacing[2] * (g.dims[2] - 1) };
}

// Calls f(i, j, k, x, y, z, linearIndex) for every voxel (world position x, y, z).
template <class F>
inline void forEachVoxel(const ImageGrid& g, F&& f)
{
  std::size_t idx = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i, ++idx)
        f(i, j, k, g.origin[0] + g.spacing[0] * i, g.origin[1] + g.spacing[1] * j,
          g.origin[2] + g.spacing[2] * k, idx);
}

struct Blob
{
  std::array<double, 3> center; // world position
  double sigma = 2.0;           // world units
  double amplitude = 1.0;
};

// Sum of isotropic Gaussian blobs A exp(-|x - c|^2 / (2 sigma^2)) at world positions,
// clamped to [0, 1] when `clampToUnit` (an opacity volume).
inline Volume gaussianBlobs(
  const ImageGrid& grid, const std::vector<Blob>& blobs, bool clampToUnit = true)
{
  Volume v;
  v.grid = grid;
  v.values.assign(grid.voxelCount(), 0.0f);
  v.name = "blobs";
  forEachVoxel(grid, [&](int, int, int, double x, double y, double z, std::size_t idx) {
    double s = 0;
    for (const Blob& b : blobs)
    {
      const double dx = x - b.center[0], dy = y - b.center[1], dz = z - b.center[2];
      const double r2 = dx * dx + dy * dy + dz * dz;
      if (r2 < 36.0 * b.sigma * b.sigma)
        s += b.amplitude * std::exp(-r2 / (2.0 * b.sigma * b.sigma));
    }
    if (clampToUnit)
      s = std::min(1.0, std::max(0.0, s));
    v.values[idx] = static_cast<float>(s);
  });
  return v;
}

// The volume "box": `inside` for voxels where inBox(i, j, k, x, y, z) holds (voxel indices
// and world position), `outside` elsewhere.
template <class InBox>
Volume boxVolumeWhere(const ImageGrid& grid, float inside, float outside, InBox inBox)
{
  Volume v;
  v.grid = grid;
  v.values.assign(grid.voxelCount(), outside);
  v.name = "box";
  forEachVoxel(grid, [&](int i, int j, int k, double x, double y, double z, std::size_t idx) {
    if (inBox(i, j, k, x, y, z))
      v.values[idx] = inside;
  });
  return v;
}

// `inside` for voxels whose world position lies in [lo, hi] (inclusive), `outside` elsewhere.
inline Volume boxVolume(const ImageGrid& grid, std::array<double, 3> lo, std::array<double, 3> hi,
  float inside = 1.0f, float outside = 0.0f)
{
  return boxVolumeWhere(grid, inside, outside, [&](int, int, int, double x, double y, double z) {
    return x >= lo[0] && x <= hi[0] && y >= lo[1] && y <= hi[1] && z >= lo[2] && z <= hi[2];
  });
}

// Same, by voxel index ranges [i0, i1] x [j0, j1] x [k0, k1] (inclusive).
inline Volume boxVolumeIndex(const ImageGrid& grid, std::array<int, 3> lo, std::array<int, 3> hi,
  float inside = 1.0f, float outside = 0.0f)
{
  return boxVolumeWhere(grid, inside, outside, [&](int i, int j, int k, double, double, double) {
    return i >= lo[0] && i <= hi[0] && j >= lo[1] && j <= hi[1] && k >= lo[2] && k <= hi[2];
  });
}

// Deterministic 64-bit generator (splitmix64): the same numbers on every platform.
struct SplitMix64
{
  std::uint64_t state;
  explicit SplitMix64(std::uint64_t seed) : state(seed) {}
  std::uint64_t next()
  {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
};

// Uniform random values in [0, 1), quantised to k/255 (uint8-like), deterministic.
inline Volume randomVolume(const ImageGrid& grid, std::uint64_t seed = 1)
{
  Volume v;
  v.grid = grid;
  v.name = "random";
  v.values.resize(grid.voxelCount());
  SplitMix64 rng(seed);
  for (float& x : v.values)
    x = static_cast<float>(rng.next() >> 56) / 255.0f;
  return v;
}

// A deterministic "structured" opacity volume of n^3 voxels (spacing 1), uint8-like
// (values k/255): a soft ellipsoidal shell (a skull-like surface), a few dozen Gaussian
// blobs of varied sizes inside it, a tilted rod, and low-amplitude noise inside the shell
// (outside it the volume is exactly 0, like air after a transfer function). It has corners,
// blobs and flat parts like a real scan, so top-N selection and ray casting do realistic
// work. Used by the CPU and GPU benchmarks.
inline Volume structuredVolume(int n, std::uint64_t seed = 7)
{
  Volume v;
  v.grid = makeGrid(n, n, n);
  v.name = "structured" + std::to_string(n);
  v.values.assign(v.grid.voxelCount(), 0.0f);
  SplitMix64 rng(seed);
  const double c = 0.5 * (n - 1);
  struct B
  {
    double x, y, z, s, a;
  };
  std::vector<B> blobs;
  for (int b = 0; b < 40; ++b)
  {
    double x, y, z;
    do
    {
      x = rng.uniform() * 2 - 1;
      y = rng.uniform() * 2 - 1;
      z = rng.uniform() * 2 - 1;
    } while (x * x + y * y + z * z > 1.0);
    blobs.push_back({ c + 0.32 * n * x, c + 0.28 * n * y, c + 0.22 * n * z,
      n * (0.012 + 0.03 * rng.uniform()), 0.5 + 0.5 * rng.uniform() });
  }
  const double ax = 0.45 * n, ay = 0.40 * n, az = 0.33 * n; // shell semi-axes
  const double shellWidth = 0.02 * n + 0.5;
  const double rodR = 0.02 * n + 0.5;
  // rod direction (normalised (1, 0.5, 0.3))
  const double rl = std::sqrt(1 + 0.25 + 0.09);
  const double rdx = 1 / rl, rdy = 0.5 / rl, rdz = 0.3 / rl;
  const std::int64_t nn = n;
#pragma omp parallel for schedule(static)
  for (std::int64_t k = 0; k < nn; ++k)
  {
    SplitMix64 noise(seed * 1000003ull + static_cast<std::uint64_t>(k));
    // Blobs that can reach this slice, then this row (exact filters: the per-voxel test
    // r2 < 16 s^2 fails for the others, so the sums are the same, in the same order).
    std::vector<const B*> inSlice, inRow;
    for (const B& b : blobs)
    {
      const double dz = static_cast<double>(k) - b.z;
      if (dz * dz < 16 * b.s * b.s)
        inSlice.push_back(&b);
    }
    for (int j = 0; j < n; ++j)
    {
      inRow.clear();
      for (const B* b : inSlice)
      {
        const double dy = j - b->y, dz = static_cast<double>(k) - b->z;
        if (dy * dy + dz * dz < 16 * b->s * b->s)
          inRow.push_back(b);
      }
      for (int i = 0; i < n; ++i)
      {
        const double x = i - c, y = j - c, z = static_cast<double>(k) - c;
        // shell: distance of the normalised radius from 1, in voxels
        const double r = std::sqrt(x * x / (ax * ax) + y * y / (ay * ay) + z * z / (az * az));
        const double shellDist = std::fabs(r - 1.0) * std::min(ax, std::min(ay, az));
        double s = 0.6 * std::exp(-shellDist * shellDist / (2 * shellWidth * shellWidth));
        for (const B* pb : inRow)
        {
          const B& b = *pb;
          const double dx = i - b.x, dy = j - b.y, dz = static_cast<double>(k) - b.z;
          const double r2 = dx * dx + dy * dy + dz * dz;
          if (r2 < 16 * b.s * b.s)
            s += b.a * std::exp(-r2 / (2 * b.s * b.s));
        }
        if (r < 1.0)
        {
          const double t = x * rdx + y * rdy + z * rdz;
          const double px = x - t * rdx, py = y - t * rdy, pz = z - t * rdz;
          const double d2 = px * px + py * py + pz * pz;
          s += 0.7 * std::exp(-d2 / (2 * rodR * rodR));
        }
        const double u = noise.uniform(); // drawn for every voxel: same sequence always
        if (r < 1.1)
          s += 0.03 * u; // low noise inside the head only: the air stays transparent
        s = std::min(1.0, std::max(0.0, s));
        v.values[static_cast<std::size_t>(k) * n * n + static_cast<std::size_t>(j) * n + i] =
          std::round(s * 255.0) / 255.0f;
      }
    }
  }
  return v;
}

// Linear map of the finite range [min, max] to [0, 1] (NaN/Inf -> 0); a constant volume
// maps to 0. A quick opacity for tests that do not go through mcv::OpacityFunction.
inline std::vector<float> rampToUnit(const Volume& v)
{
  const float lo = v.minValue(), hi = v.maxValue();
  std::vector<float> out(v.values.size(), 0.0f);
  if (!(hi > lo))
    return out;
  const float inv = 1.0f / (hi - lo);
  for (std::size_t i = 0; i < out.size(); ++i)
  {
    const float x = v.values[i];
    out[i] = std::isfinite(x) ? std::min(1.0f, std::max(0.0f, (x - lo) * inv)) : 0.0f;
  }
  return out;
}

} // namespace testing
} // namespace mcv
