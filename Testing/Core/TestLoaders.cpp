// Tests of the test-volume loaders of TestVolumes.h (NIfTI-1 and VolPack .den) and of the
// synthetic makers. GoogleTest; needs zlib (the NIfTI loader reads through gzread).
// Meant for the core test target (Testing/Core) once it links ZLIB::ZLIB.
#include "TestVolumes.h"

#include <gtest/gtest.h>

#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace
{
namespace mt = mcv::testing;

std::string tempPath(const std::string& name)
{
  const auto dir = std::filesystem::temp_directory_path() / "mcv-test-loaders";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

template <class T>
void putRaw(std::vector<unsigned char>& buf, std::size_t off, T v, bool swap)
{
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (swap)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i)
      std::swap(b[i], b[sizeof(T) - 1 - i]);
  std::memcpy(buf.data() + off, b, sizeof(T));
}

// A NIfTI-1 single file: 348-byte header, 4 bytes extension flag, then the voxels.
template <class T>
std::vector<unsigned char> makeNifti(std::vector<int> dims, std::vector<float> pixdim,
  std::int16_t datatype, const std::vector<T>& voxels, bool swap, float slope = 0,
  float inter = 0)
{
  std::vector<unsigned char> buf(352 + voxels.size() * sizeof(T), 0);
  putRaw<std::int32_t>(buf, 0, 348, swap);
  putRaw<std::int16_t>(buf, 40, static_cast<std::int16_t>(dims.size()), swap);
  for (std::size_t i = 0; i < dims.size(); ++i)
    putRaw<std::int16_t>(buf, 42 + 2 * i, static_cast<std::int16_t>(dims[i]), swap);
  putRaw<std::int16_t>(buf, 70, datatype, swap);
  putRaw<std::int16_t>(buf, 72, static_cast<std::int16_t>(8 * sizeof(T)), swap);
  putRaw<float>(buf, 76, 1.0f, swap); // qfac
  for (std::size_t i = 0; i < pixdim.size(); ++i)
    putRaw<float>(buf, 80 + 4 * i, pixdim[i], swap);
  putRaw<float>(buf, 108, 352.0f, swap);
  putRaw<float>(buf, 112, slope, swap);
  putRaw<float>(buf, 116, inter, swap);
  std::memcpy(buf.data() + 344, "n+1", 4);
  for (std::size_t i = 0; i < voxels.size(); ++i)
    putRaw<T>(buf, 352 + i * sizeof(T), voxels[i], swap);
  return buf;
}

void writeFile(const std::string& path, const std::vector<unsigned char>& bytes, bool gz)
{
  if (gz)
  {
    gzFile f = gzopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(gzwrite(f, bytes.data(), static_cast<unsigned>(bytes.size())),
      static_cast<int>(bytes.size()));
    gzclose(f);
  }
  else
  {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
}

template <class T>
void roundTrip(std::int16_t datatype, bool swap, bool gz)
{
  const std::vector<int> dims = { 3, 4, 2 };
  std::vector<T> voxels;
  for (int i = 0; i < 3 * 4 * 2; ++i)
    voxels.push_back(static_cast<T>(i * 3 - (std::is_signed<T>::value ? 20 : 0)));
  const auto bytes = makeNifti<T>(dims, { 0.5f, -2.0f, 3.0f }, datatype, voxels, swap);
  const std::string path =
    tempPath("rt_" + std::to_string(datatype) + (swap ? "_be" : "_le") + (gz ? ".nii.gz" : ".nii"));
  writeFile(path, bytes, gz);
  const mt::Volume v = mt::loadNifti(path);
  EXPECT_EQ(v.grid.dims, (std::array<int, 3>{ 3, 4, 2 })) << path;
  EXPECT_EQ(v.grid.spacing, (std::array<double, 3>{ 0.5, 2.0, 3.0 })) << path; // |pixdim|
  ASSERT_EQ(v.values.size(), voxels.size());
  for (std::size_t i = 0; i < voxels.size(); ++i)
    EXPECT_EQ(v.values[i], static_cast<float>(voxels[i])) << path << " voxel " << i;
}

TEST(NiftiLoader, EachScalarTypeBothByteOrdersPlainAndGzip)
{
  for (bool swap : { false, true })
    for (bool gz : { false, true })
    {
      roundTrip<std::uint8_t>(2, swap, gz);
      roundTrip<std::int16_t>(4, swap, gz);
      roundTrip<std::uint16_t>(512, swap, gz);
      roundTrip<std::int32_t>(8, swap, gz);
      roundTrip<float>(16, swap, gz);
      roundTrip<double>(64, swap, gz);
    }
}

TEST(NiftiLoader, FourDimensionalVolumesAndScaling)
{
  // 2x2x2 x 3 volumes, volume t holds 100 t + i; scl_slope 2, scl_inter 1.
  std::vector<std::int16_t> voxels;
  for (int t = 0; t < 3; ++t)
    for (int i = 0; i < 8; ++i)
      voxels.push_back(static_cast<std::int16_t>(100 * t + i));
  const auto bytes = makeNifti<std::int16_t>({ 2, 2, 2, 3 }, { 1, 1, 1, 1 }, 4, voxels, false, 2, 1);
  const std::string path = tempPath("four_d.nii.gz");
  writeFile(path, bytes, true);
  EXPECT_EQ(mt::niftiVolumeCount(path), 3);
  const auto first = mt::loadNifti(path);
  EXPECT_EQ(first.values[5], 2.0f * 5 + 1);
  const auto third = mt::loadNifti(path, 2);
  EXPECT_EQ(third.values[7], 2.0f * 207 + 1);
  const auto all = mt::loadNiftiVolumes(path, 0, 3);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[1].values[0], 2.0f * 100 + 1);
  EXPECT_THROW(mt::loadNifti(path, 3), std::runtime_error);
  EXPECT_THROW(mt::loadNifti(path, -1), std::runtime_error);
}

TEST(NiftiLoader, BadFilesThrowWithTheFileName)
{
  const std::string missing = tempPath("does_not_exist.nii");
  try
  {
    mt::loadNifti(missing);
    FAIL() << "no exception";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  std::vector<std::uint8_t> voxels(8, 1);
  auto bytes = makeNifti<std::uint8_t>({ 2, 2, 2 }, { 1, 1, 1 }, 2, voxels, false);
  // Truncated data.
  auto shortBytes = bytes;
  shortBytes.resize(bytes.size() - 3);
  writeFile(tempPath("truncated.nii"), shortBytes, false);
  EXPECT_THROW(mt::loadNifti(tempPath("truncated.nii")), std::runtime_error);
  // Bad magic.
  auto badMagic = bytes;
  std::memcpy(badMagic.data() + 344, "xyz", 4);
  writeFile(tempPath("badmagic.nii"), badMagic, false);
  EXPECT_THROW(mt::loadNifti(tempPath("badmagic.nii")), std::runtime_error);
  // Unsupported datatype (complex64 = 32).
  auto complex = bytes;
  putRaw<std::int16_t>(complex, 70, 32, false);
  writeFile(tempPath("complex.nii"), complex, false);
  EXPECT_THROW(mt::loadNifti(tempPath("complex.nii")), std::runtime_error);
}

std::vector<unsigned char> makeDen(int nx, int ny, int nz, bool swap)
{
  std::vector<unsigned char> buf(62 + static_cast<std::size_t>(nx) * ny * nz);
  putRaw<std::int16_t>(buf, 0, 1, swap);
  const int len[3] = { nx, ny, nz };
  for (int a = 0; a < 3; ++a)
  {
    putRaw<std::int16_t>(buf, 14 + 2 * a, static_cast<std::int16_t>(2 * len[a]), swap); // orig_len
    putRaw<std::int16_t>(buf, 32 + 2 * a, static_cast<std::int16_t>(2 * len[a]), swap); // extr_len
    putRaw<std::int16_t>(buf, 44 + 2 * a, static_cast<std::int16_t>(len[a] - 1), swap); // map_max
    putRaw<std::int16_t>(buf, 50 + 2 * a, static_cast<std::int16_t>(len[a]), swap);     // map_len
  }
  putRaw<std::int32_t>(buf, 58, nx * ny * nz, swap);
  for (int i = 0; i < nx * ny * nz; ++i)
    buf[62 + i] = static_cast<unsigned char>(i * 7);
  return buf;
}

TEST(VolPackLoader, BothByteOrdersAndErrors)
{
  for (bool swap : { false, true })
  {
    const std::string path = tempPath(swap ? "be.den" : "le.den");
    writeFile(path, makeDen(5, 4, 3, swap), false);
    const auto v = mt::loadVolPackDen(path);
    EXPECT_EQ(v.grid.dims, (std::array<int, 3>{ 5, 4, 3 }));
    EXPECT_EQ(v.grid.spacing, (std::array<double, 3>{ 1, 1, 1 }));
    ASSERT_EQ(v.values.size(), 60u);
    for (int i = 0; i < 60; ++i)
      EXPECT_EQ(v.values[i], static_cast<float>(static_cast<unsigned char>(i * 7)));
    const auto aspect = mt::loadVolPackDen(path, true);
    EXPECT_EQ(aspect.grid.spacing, (std::array<double, 3>{ 2, 2, 2 }));
  }
  auto bad = makeDen(5, 4, 3, false);
  putRaw<std::int32_t>(bad, 58, 59, false); // inconsistent map_length
  writeFile(tempPath("bad.den"), bad, false);
  EXPECT_THROW(mt::loadVolPackDen(tempPath("bad.den")), std::runtime_error);
  auto truncated = makeDen(5, 4, 3, false);
  truncated.resize(100);
  writeFile(tempPath("truncated.den"), truncated, false);
  EXPECT_THROW(mt::loadVolPackDen(tempPath("truncated.den")), std::runtime_error);
}

// ------------------------------------------------------------------ the real volumes

TEST(RealVolumes, Colin27AndAtlasesShareAGrid)
{
  for (const char* name : { "ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz" })
  {
    if (!mt::haveDataFile(name))
      GTEST_SKIP() << mt::dataFile(name) << " missing: run scripts/fetch-data.sh";
    const auto v = mt::loadNifti(mt::dataFile(name));
    EXPECT_EQ(v.grid.dims, (std::array<int, 3>{ 181, 217, 181 })) << name;
    EXPECT_EQ(v.grid.spacing, (std::array<double, 3>{ 1, 1, 1 })) << name;
    EXPECT_GE(v.minValue(), 0.0f) << name;
    EXPECT_LE(v.maxValue(), 255.0f) << name;
    EXPECT_GT(v.maxValue(), 40.0f) << name; // brodmann: areas 1..48
  }
}

TEST(RealVolumes, BrainsmallDen)
{
  if (!mt::haveDataFile("brainsmall.den"))
    GTEST_SKIP() << "brainsmall.den missing: run scripts/fetch-data.sh";
  const auto v = mt::loadVolPackDen(mt::dataFile("brainsmall.den"));
  EXPECT_EQ(v.grid.dims, (std::array<int, 3>{ 128, 128, 84 }));
  EXPECT_GT(v.maxValue(), 100.0f);
  const auto aspect = mt::loadVolPackDen(mt::dataFile("brainsmall.den"), true);
  EXPECT_NEAR(aspect.grid.spacing[0], 2.0, 1e-12);
  EXPECT_NEAR(aspect.grid.spacing[2], 109.0 / 84.0, 1e-12);
}

TEST(RealVolumes, DipySmall64D)
{
  if (!mt::haveDataFile("small_64D.nii"))
    GTEST_SKIP() << "small_64D.nii missing: run scripts/fetch-data.sh";
  const std::string path = mt::dataFile("small_64D.nii");
  EXPECT_EQ(mt::niftiVolumeCount(path), 65);
  const auto v = mt::loadNifti(path, 64);
  EXPECT_EQ(v.grid.dims, (std::array<int, 3>{ 10, 10, 10 }));
  EXPECT_EQ(v.grid.spacing, (std::array<double, 3>{ 2, 2, 2 }));
  EXPECT_GT(v.maxValue(), 0.0f);
}

// ------------------------------------------------------------------ synthetic makers

TEST(SyntheticVolumes, BlobsBoxesAndDeterminism)
{
  const auto grid = mt::makeGrid(21, 21, 21, { 0.5, 0.5, 0.5 }, { -5, -5, -5 });
  const auto blobs = mt::gaussianBlobs(grid, { { { 0, 0, 0 }, 1.0, 1.0 } });
  // Peak at the world origin = voxel (10, 10, 10); one sigma away: exp(-1/2).
  EXPECT_FLOAT_EQ(blobs.values[(10 * 21 + 10) * 21 + 10], 1.0f);
  EXPECT_NEAR(blobs.values[(10 * 21 + 10) * 21 + 12], std::exp(-0.5), 1e-6);
  const auto box = mt::boxVolume(grid, { -1, -1, -1 }, { 1, 1, 1 }, 0.5f);
  std::size_t inside = 0;
  for (float x : box.values)
    inside += x == 0.5f;
  EXPECT_EQ(inside, 5u * 5 * 5);
  const auto a = mt::structuredVolume(32), b = mt::structuredVolume(32);
  EXPECT_EQ(a.values, b.values);
  for (float x : a.values)
  {
    ASSERT_GE(x, 0.0f);
    ASSERT_LE(x, 1.0f);
    ASSERT_EQ(std::round(x * 255.0f), x * 255.0f);
  }
  EXPECT_EQ(mt::randomVolume(grid, 3).values, mt::randomVolume(grid, 3).values);
  EXPECT_NE(mt::randomVolume(grid, 3).values, mt::randomVolume(grid, 4).values);
}

} // namespace
