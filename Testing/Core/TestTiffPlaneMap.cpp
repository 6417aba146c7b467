// The plane maps of ImageJ hyperstacks and OME-TIFF files (Filters/IO/ImageJHyperstack.h,
// OMETiffMetadata.h, TiffPlaneMap.h): which page holds channel c, slice z, frame t for every
// axis order; spacing, units, times and channel names as the files write them (the
// descriptions below are those tifffile 2023.2 and Bio-Formats write); and each bad file
// refused with a message that says what is wrong.
#include "ImageJHyperstack.h"
#include "OMETiffMetadata.h"
#include "TiffPlaneMap.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace
{

using mcv::TiffPlaneMap;

bool contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}

// tifffile's description for axes TZCYX: 2 frames, 3 slices, 2 channels.
const char* kHyperstack = "ImageJ=1.11a\nimages=12\nchannels=2\nslices=3\nframes=2\n"
                          "hyperstack=true\nmode=grayscale\nloop=false\nspacing=2.0\n"
                          "unit=um\nfinterval=3.5";

mcv::ImageJTags imagej(const std::string& description, double xres = 2.0, double yres = 4.0)
{
  mcv::ImageJTags tags;
  tags.Description = description;
  tags.XResolution = xres;
  tags.YResolution = yres;
  return tags;
}

// IJMetadata with the given slice labels, as tifffile writes it (UTF-16 in file order).
void addLabels(mcv::ImageJTags& tags, const std::vector<std::string>& labels, bool bigEndian)
{
  auto u32 = [&](std::uint32_t v) {
    std::string b(4, '\0');
    for (int i = 0; i < 4; ++i)
    {
      b[bigEndian ? i : 3 - i] = static_cast<char>((v >> (24 - 8 * i)) & 0xff);
    }
    return b;
  };
  tags.BigEndian = bigEndian;
  tags.Metadata = u32(0x494a494a) + u32(0x6c61626c) + // "IJIJ", "labl"
    u32(static_cast<std::uint32_t>(labels.size()));
  tags.MetadataByteCounts = { 12 };
  for (const std::string& label : labels)
  {
    std::string utf16;
    for (char ch : label)
    {
      utf16 += bigEndian ? std::string(1, '\0') + ch : std::string(1, ch) + '\0';
    }
    tags.Metadata += utf16;
    tags.MetadataByteCounts.push_back(utf16.size());
  }
}

// Every plane of a 2-channel, 3-slice, 2-frame map in file 0, at page pageOf(c, z, t).
template <class PageOf>
void expectPagesOfOneFile(const TiffPlaneMap& map, PageOf pageOf)
{
  for (int t = 0; t < 2; ++t)
    for (int z = 0; z < 3; ++z)
      for (int c = 0; c < 2; ++c)
      {
        SCOPED_TRACE("c " + std::to_string(c) + " z " + std::to_string(z) + " t " + std::to_string(t));
        EXPECT_EQ(map.At(c, z, t).File, 0);
        EXPECT_EQ(map.At(c, z, t).Page, static_cast<std::uint64_t>(pageOf(c, z, t)));
      }
}

TEST(ImageJHyperstack, TZCYXPagesChannelFastestThenSliceThenFrame)
{
  TiffPlaneMap map;
  ASSERT_EQ(mcv::parseImageJ(imagej(kHyperstack), 12, map), "");
  EXPECT_EQ(map.SizeC, 2);
  EXPECT_EQ(map.SizeZ, 3);
  EXPECT_EQ(map.SizeT, 2);
  // ImageJ's page order: channel fastest, then slice, then frame.
  expectPagesOfOneFile(map, [](int c, int z, int t) { return (t * 3 + z) * 2 + c; });
  EXPECT_DOUBLE_EQ(map.Spacing[0], 0.5);  // 1 / XResolution
  EXPECT_DOUBLE_EQ(map.Spacing[1], 0.25); // 1 / YResolution
  EXPECT_DOUBLE_EQ(map.Spacing[2], 2.0);  // spacing=
  EXPECT_EQ(map.LengthUnit, "µm");
  EXPECT_EQ(map.TimeValues, (std::vector<double>{ 0.0, 3.5 }));
  EXPECT_EQ(map.TimeUnit, "s");
  EXPECT_EQ(map.ChannelNames, (std::vector<std::string>{ "C1", "C2" }));
  map.Files = { "h.tif" };
  EXPECT_EQ(mcv::checkPlaneMap(map, { 12 }), "");
}

TEST(ImageJHyperstack, SubsetsOfTZCYX)
{
  // ZCYX (no frames=, no finterval=): one frame at time 0, in frames.
  TiffPlaneMap map;
  ASSERT_EQ(mcv::parseImageJ(imagej("ImageJ=1.11a\nimages=6\nchannels=2\nslices=3\n"
                                    "hyperstack=true\nunit=micron\nspacing=1.5"),
              6, map),
    "");
  EXPECT_EQ(map.SizeT, 1);
  EXPECT_EQ(map.At(1, 2, 0).Page, 5u);
  EXPECT_EQ(map.TimeValues, (std::vector<double>{ 0.0 }));
  EXPECT_EQ(map.TimeUnit, "frame");
  EXPECT_EQ(map.LengthUnit, "µm");
  // TCYX: slices= absent, taken from images / (channels x frames).
  ASSERT_EQ(mcv::parseImageJ(imagej("ImageJ=1.11a\nimages=4\nchannels=2\nframes=2\n"), 4, map), "");
  EXPECT_EQ(map.SizeZ, 1);
  EXPECT_EQ(map.At(1, 0, 1).Page, 3u);
  EXPECT_EQ(map.TimeValues, (std::vector<double>{ 0.0, 1.0 }));
  // ZYX without unit and resolution: pixels, spacing 1.
  ASSERT_EQ(mcv::parseImageJ(imagej("ImageJ=1.11a\nimages=5\nslices=5\n", 0, 0), 5, map), "");
  EXPECT_EQ(map.SizeC, 1);
  EXPECT_EQ(map.SizeZ, 5);
  EXPECT_EQ(map.LengthUnit, "pixel");
  EXPECT_DOUBLE_EQ(map.Spacing[0], 1.0);
  EXPECT_DOUBLE_EQ(map.Spacing[1], 1.0);
  EXPECT_DOUBLE_EQ(map.Spacing[2], 1.0);
}

TEST(ImageJHyperstack, ChannelNamesFromSliceLabels)
{
  for (bool big : { false, true })
  {
    mcv::ImageJTags tags = imagej("ImageJ=1.11a\nimages=4\nchannels=2\nslices=2\n");
    addLabels(tags, { "DAPI", "GFP", "DAPI", "GFP" }, big);
    EXPECT_EQ(mcv::imageJLabels(tags), (std::vector<std::string>{ "DAPI", "GFP", "DAPI", "GFP" }));
    TiffPlaneMap map;
    ASSERT_EQ(mcv::parseImageJ(tags, 4, map), "");
    EXPECT_EQ(map.ChannelNames, (std::vector<std::string>{ "DAPI", "GFP" }));
  }
  // Repeated or empty labels still give distinct names.
  mcv::ImageJTags tags = imagej("ImageJ=1.11a\nimages=3\nchannels=3\n");
  addLabels(tags, { "a", "a", "" }, false);
  TiffPlaneMap map;
  ASSERT_EQ(mcv::parseImageJ(tags, 3, map), "");
  EXPECT_EQ(map.ChannelNames, (std::vector<std::string>{ "a", "C2", "C3" }));
  // A malformed tag (counts beyond its bytes) gives no labels, not an error.
  tags.MetadataByteCounts.push_back(1000);
  tags.MetadataByteCounts[0] = 12;
  tags.Metadata = tags.Metadata.substr(0, 14);
  EXPECT_TRUE(mcv::imageJLabels(tags).empty());
}

TEST(ImageJHyperstack, BadDescriptionsAreRefused)
{
  TiffPlaneMap map;
  const std::string wrongCount = mcv::parseImageJ(
    imagej("ImageJ=1.11a\nimages=12\nchannels=2\nslices=3\nframes=3\n"), 18, map);
  EXPECT_TRUE(contains(wrongCount, "images=12")) << wrongCount;
  EXPECT_TRUE(contains(wrongCount, "channels=2 x slices=3 x frames=3 = 18")) << wrongCount;
  const std::string missing = mcv::parseImageJ(imagej(kHyperstack), 7, map);
  EXPECT_TRUE(contains(missing, "is missing pages")) << missing;
  EXPECT_TRUE(contains(missing, "holds 7 pages")) << missing;
  const std::string unit =
    mcv::parseImageJ(imagej("ImageJ=1.11a\nimages=2\nslices=2\nunit=furlong\n"), 2, map);
  EXPECT_TRUE(contains(unit, "unit=furlong")) << unit;
  EXPECT_TRUE(contains(unit, "does not know")) << unit;
  EXPECT_NE(mcv::parseImageJ(imagej("ImageJ=1.11a\nimages=2\nchannels=x\n"), 2, map), "");
  EXPECT_NE(mcv::parseImageJ(imagej("ImageJ=1.11a\nimages=2\nslices=2\nspacing=0\n"), 2, map), "");
  EXPECT_NE(
    mcv::parseImageJ(imagej("ImageJ=1.11a\nimages=2\nframes=2\nfinterval=-1\n"), 2, map), "");
}

// OME-XML as tifffile writes it for axes TCZYX (DimensionOrder XYZCT), with PhysicalSize in nm.
std::string tifffileOME(const std::string& order = "XYZCT", const std::string& extra = "",
  const std::string& sizeC = "2", const std::string& unit = "nm",
  const std::string& tiffData = "<TiffData IFD=\"0\" PlaneCount=\"12\"/>")
{
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?><OME "
         "xmlns=\"http://www.openmicroscopy.org/Schemas/OME/2016-06\" Creator=\"tifffile.py "
         "2023.2.3\"><Image ID=\"Image:0\" Name=\"Image0\"><Pixels ID=\"Pixels:0\" "
         "DimensionOrder=\"" +
    order + "\" Type=\"uint16\" SizeX=\"4\" SizeY=\"5\" SizeZ=\"3\" SizeC=\"" + sizeC +
    "\" SizeT=\"2\" PhysicalSizeX=\"500\" PhysicalSizeXUnit=\"" + unit +
    "\" PhysicalSizeY=\"250\" PhysicalSizeYUnit=\"nm\" PhysicalSizeZ=\"2.0\" "
    "TimeIncrement=\"3.5\" " +
    extra +
    "><Channel ID=\"Channel:0:0\" SamplesPerPixel=\"1\" Name=\"ch2\"><LightPath/></Channel>"
    "<Channel ID=\"Channel:0:1\" SamplesPerPixel=\"1\" Name=\"aal\"><LightPath/></Channel>" +
    tiffData + "</Pixels></Image></OME>";
}

TEST(OMETiffMetadata, TifffileFileXYZCT)
{
  ASSERT_TRUE(mcv::isOMEDescription(tifffileOME()));
  EXPECT_FALSE(mcv::isOMEDescription(kHyperstack));
  TiffPlaneMap map;
  ASSERT_EQ(mcv::parseOME(tifffileOME(), "x.ome.tif", map), "");
  EXPECT_EQ(map.SizeX, 4u);
  EXPECT_EQ(map.SizeY, 5u);
  EXPECT_EQ(map.SizeZ, 3);
  EXPECT_EQ(map.SizeC, 2);
  EXPECT_EQ(map.SizeT, 2);
  EXPECT_EQ(map.BitsPerSample, 16);
  EXPECT_EQ(map.SampleFormat, 1);
  expectPagesOfOneFile(map, [](int c, int z, int t) { return z + 3 * (c + 2 * t); });
  EXPECT_DOUBLE_EQ(map.Spacing[0], 0.5);  // 500 nm in µm
  EXPECT_DOUBLE_EQ(map.Spacing[1], 0.25); // 250 nm
  EXPECT_DOUBLE_EQ(map.Spacing[2], 2.0);  // µm, the default unit
  EXPECT_EQ(map.LengthUnit, "µm");
  EXPECT_EQ(map.TimeValues, (std::vector<double>{ 0.0, 3.5 }));
  EXPECT_EQ(map.TimeUnit, "s");
  EXPECT_EQ(map.ChannelNames, (std::vector<std::string>{ "ch2", "aal" }));
  EXPECT_EQ(map.Files, (std::vector<std::string>{ "x.ome.tif" }));
  EXPECT_EQ(mcv::checkPlaneMap(map, { 12 }), "");
  EXPECT_EQ(map.Warning, "");
  // A second image (series): the first is read, with a warning that names the count.
  std::string two = tifffileOME();
  two.insert(two.find("</OME>"), "<Image ID=\"Image:1\" Name=\"Image1\"/>");
  ASSERT_EQ(mcv::parseOME(two, "x.ome.tif", map), "");
  EXPECT_EQ(map.Warning,
    "holds 2 images (series) in its OME-XML; only the first ('Image0') is read");
}

TEST(OMETiffMetadata, AllSixDimensionOrders)
{
  // Without TiffData, the pages hold the planes in DimensionOrder (fastest first).
  for (const std::string order : { "XYZCT", "XYZTC", "XYCTZ", "XYCZT", "XYTCZ", "XYTZC" })
  {
    TiffPlaneMap map;
    ASSERT_EQ(mcv::parseOME(tifffileOME(order, "", "2", "nm", ""), "x.ome.tif", map), "") << order;
    const int size[3] = { 3, 2, 2 }; // Z, C, T
    for (int t = 0; t < 2; ++t)
      for (int c = 0; c < 2; ++c)
        for (int z = 0; z < 3; ++z)
        {
          const int zct[3] = { z, c, t };
          std::uint64_t page = 0, stride = 1;
          for (int i = 2; i < 5; ++i)
          {
            const int axis = order[i] == 'Z' ? 0 : order[i] == 'C' ? 1 : 2;
            page += zct[axis] * stride;
            stride *= size[axis];
          }
          EXPECT_EQ(map.At(c, z, t).Page, page) << order << " c" << c << " z" << z << " t" << t;
        }
    EXPECT_EQ(mcv::checkPlaneMap(map, { 12 }), "") << order;
  }
}

TEST(OMETiffMetadata, BioFormatsTiffDataPerPlaneAndFileSets)
{
  // One TiffData per plane (Bio-Formats), in no particular order; frame 2 in another file
  // of the set (UUID FileName), the OME namespace under a prefix.
  std::string blocks;
  for (int t = 1; t >= 0; --t)
    for (int z = 0; z < 3; ++z)
      for (int c = 0; c < 2; ++c)
      {
        const int ifd = c + 2 * z; // XYCZT within each file
        blocks += "<ome:TiffData FirstC=\"" + std::to_string(c) + "\" FirstZ=\"" +
          std::to_string(z) + "\" FirstT=\"" + std::to_string(t) + "\" IFD=\"" +
          std::to_string(ifd) + "\" PlaneCount=\"1\">" +
          (t == 1 ? "<ome:UUID FileName=\"set_t1.ome.tif\">urn:uuid:2</ome:UUID>"
                  : "<ome:UUID FileName=\"set_t0.ome.tif\">urn:uuid:1</ome:UUID>") +
          "</ome:TiffData>";
      }
  const std::string xml = "<?xml version=\"1.0\"?><ome:OME "
                          "xmlns:ome=\"http://www.openmicroscopy.org/Schemas/OME/2016-06\">"
                          "<ome:Image ID=\"Image:0\"><ome:Pixels DimensionOrder=\"XYCZT\" "
                          "Type=\"float\" SizeX=\"4\" SizeY=\"5\" SizeZ=\"3\" SizeC=\"2\" "
                          "SizeT=\"2\" PhysicalSizeZ=\"0.002\" PhysicalSizeZUnit=\"mm\" "
                          "TimeIncrement=\"500\" TimeIncrementUnit=\"ms\">"
                          "<ome:Channel Name=\"ch2\"/><ome:Channel Name=\"aal\"/>" +
    blocks + "</ome:Pixels></ome:Image></ome:OME>";
  TiffPlaneMap map;
  ASSERT_EQ(mcv::parseOME(xml, "set_t0.ome.tif", map), "");
  EXPECT_EQ(map.Files, (std::vector<std::string>{ "set_t0.ome.tif", "set_t1.ome.tif" }));
  EXPECT_EQ(map.SampleFormat, 3);
  for (int t = 0; t < 2; ++t)
    for (int z = 0; z < 3; ++z)
      for (int c = 0; c < 2; ++c)
      {
        EXPECT_EQ(map.At(c, z, t).File, t);
        EXPECT_EQ(map.At(c, z, t).Page, static_cast<std::uint64_t>(c + 2 * z));
      }
  EXPECT_DOUBLE_EQ(map.Spacing[0], 1.0); // no PhysicalSizeX: 1
  EXPECT_DOUBLE_EQ(map.Spacing[2], 2.0); // 0.002 mm in µm
  EXPECT_EQ(map.TimeValues, (std::vector<double>{ 0.0, 0.5 }));
  EXPECT_EQ(mcv::checkPlaneMap(map, { 6, 6 }), "");
  const std::string short_ = mcv::checkPlaneMap(map, { 6, 5 });
  EXPECT_TRUE(contains(short_, "on page 6 of 'set_t1.ome.tif', which holds 5 pages")) << short_;
}

TEST(OMETiffMetadata, BadFilesAreRefused)
{
  TiffPlaneMap map;
  const std::string channels = mcv::parseOME(tifffileOME("XYZCT", "", "3"), "x.ome.tif", map);
  EXPECT_TRUE(contains(channels, "SizeC=3 in its OME-XML but 2 Channel elements")) << channels;
  const std::string past = mcv::parseOME(
    tifffileOME("XYZCT", "", "2", "nm", "<TiffData IFD=\"0\" PlaneCount=\"13\"/>"), "x.ome.tif",
    map);
  EXPECT_TRUE(contains(past, "TiffData (number 1)")) << past;
  EXPECT_TRUE(contains(past, "past the SizeZ x SizeC x SizeT = 12 planes")) << past;
  const std::string unit =
    mcv::parseOME(tifffileOME("XYZCT", "", "2", "furlong"), "x.ome.tif", map);
  EXPECT_TRUE(contains(unit, "PhysicalSizeXUnit=\"furlong\"")) << unit;
  const std::string order = mcv::parseOME(tifffileOME("XYZZT"), "x.ome.tif", map);
  EXPECT_TRUE(contains(order, "DimensionOrder=\"XYZZT\"")) << order;
  const std::string xml = mcv::parseOME("<OME><Image><Pixels", "x.ome.tif", map);
  EXPECT_TRUE(contains(xml, "cannot be parsed")) << xml;
  std::string type = tifffileOME();
  type.replace(type.find("uint16"), 6, "double");
  const std::string typeProblem = mcv::parseOME(type, "x.ome.tif", map);
  EXPECT_TRUE(contains(typeProblem, "Type=\"double\"")) << typeProblem;
  // Planes that no TiffData maps, and a page beyond the file.
  ASSERT_EQ(mcv::parseOME(tifffileOME("XYZCT", "", "2", "nm", "<TiffData PlaneCount=\"11\"/>"),
              "x.ome.tif", map),
    "");
  const std::string missing = mcv::checkPlaneMap(map, { 12 });
  EXPECT_TRUE(contains(missing, "no page for channel 2, slice 3, frame 2")) << missing;
  ASSERT_EQ(mcv::parseOME(tifffileOME(), "x.ome.tif", map), "");
  const std::string beyond = mcv::checkPlaneMap(map, { 10 });
  EXPECT_TRUE(contains(beyond, "on page 11 of 'x.ome.tif', which holds 10 pages")) << beyond;
}

} // namespace
