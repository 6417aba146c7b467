#include "OMETiffMetadata.h"

#include <pugixml.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>

namespace mcv
{
namespace
{
// A node's name without its namespace prefix ("ome:Pixels" -> "Pixels").
const char* localName(const pugi::xml_node& node)
{
  const char* name = node.name();
  const char* colon = std::strrchr(name, ':');
  return colon ? colon + 1 : name;
}

pugi::xml_node child(const pugi::xml_node& node, const char* name)
{
  for (pugi::xml_node c : node.children())
  {
    if (c.type() == pugi::node_element && std::strcmp(localName(c), name) == 0)
    {
      return c;
    }
  }
  return {};
}

std::vector<pugi::xml_node> children(const pugi::xml_node& node, const char* name)
{
  std::vector<pugi::xml_node> found;
  for (pugi::xml_node c : node.children())
  {
    if (c.type() == pugi::node_element && std::strcmp(localName(c), name) == 0)
    {
      found.push_back(c);
    }
  }
  return found;
}

bool toNumber(const char* text, double& value)
{
  if (!text || !*text)
  {
    return false;
  }
  char* end = nullptr;
  value = std::strtod(text, &end);
  while (end && (*end == ' ' || *end == '\t'))
  {
    ++end;
  }
  return end && *end == '\0';
}

// Micrometres per unit of OME's UnitsLength symbols; 0 when unknown.
double micrometres(const std::string& unit)
{
  static const std::map<std::string, double> units = { { "pm", 1e-6 }, { "Å", 1e-4 },
    { "nm", 1e-3 }, { "µm", 1 }, { "\xb5m", 1 }, { "um", 1 }, { "mm", 1e3 }, { "cm", 1e4 },
    { "dm", 1e5 }, { "m", 1e6 } };
  const auto found = units.find(unit);
  return found == units.end() ? 0 : found->second;
}

// Seconds per unit of OME's UnitsTime symbols; 0 when unknown.
double seconds(const std::string& unit)
{
  static const std::map<std::string, double> units = { { "ns", 1e-9 }, { "µs", 1e-6 },
    { "\xb5s", 1e-6 }, { "us", 1e-6 }, { "ms", 1e-3 }, { "s", 1 }, { "min", 60 },
    { "h", 3600 } };
  const auto found = units.find(unit);
  return found == units.end() ? 0 : found->second;
}
} // namespace

//------------------------------------------------------------------------------
bool isOMEDescription(const std::string& description)
{
  const std::size_t start = description.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || description[start] != '<')
  {
    return false;
  }
  return description.find("<OME") != std::string::npos ||
    description.find(":OME") != std::string::npos;
}

//------------------------------------------------------------------------------
std::string parseOME(const std::string& xml, const std::string& fileName, TiffPlaneMap& map)
{
  std::ostringstream msg;
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(xml.data(), xml.size());
  if (!parsed)
  {
    msg << "has OME-XML that cannot be parsed (" << parsed.description() << " at character "
        << parsed.offset << ")";
    return msg.str();
  }
  const pugi::xml_node ome = doc.document_element();
  const pugi::xml_node image = child(ome, "Image");
  const pugi::xml_node pixels = image ? child(image, "Pixels") : pugi::xml_node();
  if (std::strcmp(localName(ome), "OME") != 0 || !pixels)
  {
    return child(ome, "BinaryOnly")
      ? "holds only a reference to its OME-XML in another file (BinaryOnly), which this "
        "reader does not follow: open the file that holds the OME-XML"
      : "has OME-XML without an Image with Pixels";
  }

  // Sizes: positive whole numbers.
  std::uint64_t sizes[5] = {};
  const char* names[5] = { "SizeX", "SizeY", "SizeZ", "SizeC", "SizeT" };
  for (int i = 0; i < 5; ++i)
  {
    double value = 0;
    const char* text = pixels.attribute(names[i]).value();
    if (!toNumber(text, value) || value < 1 || value != std::floor(value) ||
      value > (i < 2 ? 4294967295.0 : 2147483647.0))
    {
      msg << "has " << names[i] << "=\"" << text
          << "\" in its OME-XML (a whole number of at least 1 expected)";
      return msg.str();
    }
    sizes[i] = static_cast<std::uint64_t>(value);
  }
  map.Format = "OME-TIFF";
  const std::size_t images = children(ome, "Image").size();
  if (images > 1)
  {
    std::ostringstream warning;
    warning << "holds " << images << " images (series) in its OME-XML; only the first ('"
            << image.attribute("Name").value() << "') is read";
    map.Warning = warning.str();
  }
  map.SizeX = sizes[0];
  map.SizeY = sizes[1];
  map.SizeZ = static_cast<int>(sizes[2]);
  map.SizeC = static_cast<int>(sizes[3]);
  map.SizeT = static_cast<int>(sizes[4]);
  if (!map.Allocate())
  {
    msg << "has SizeZ x SizeC x SizeT = " << sizes[2] * sizes[3] * sizes[4]
        << " planes in its OME-XML, more than this reader can index";
    return msg.str();
  }

  // The sample type.
  static const std::map<std::string, std::pair<int, int>> types = { { "uint8", { 8, 1 } },
    { "int8", { 8, 2 } }, { "uint16", { 16, 1 } }, { "int16", { 16, 2 } },
    { "uint32", { 32, 1 } }, { "int32", { 32, 2 } }, { "float", { 32, 3 } } };
  const std::string type = pixels.attribute("Type").value();
  const auto known = types.find(type);
  if (known == types.end())
  {
    msg << "has Type=\"" << type << "\" in its OME-XML, which this reader does not read "
        << "(uint8, int8, uint16, int16, uint32, int32 and float are read)";
    return msg.str();
  }
  map.BitsPerSample = known->second.first;
  map.SampleFormat = known->second.second;

  // The order of the planes: XY, then Z, C and T in some order (fastest first).
  const std::string order = pixels.attribute("DimensionOrder").value();
  static const char* orders[] = { "XYZCT", "XYZTC", "XYCTZ", "XYCZT", "XYTCZ", "XYTZC" };
  bool orderKnown = false;
  for (const char* o : orders)
  {
    orderKnown = orderKnown || order == o;
  }
  if (!orderKnown)
  {
    msg << "has DimensionOrder=\"" << order << "\" in its OME-XML (one of XYZCT, XYZTC, "
        << "XYCTZ, XYCZT, XYTCZ, XYTZC expected)";
    return msg.str();
  }

  // Spacing in µm.
  const char* axes[3] = { "X", "Y", "Z" };
  for (int a = 0; a < 3; ++a)
  {
    const std::string size = std::string("PhysicalSize") + axes[a];
    const pugi::xml_attribute value = pixels.attribute(size.c_str());
    const pugi::xml_attribute unit = pixels.attribute((size + "Unit").c_str());
    double spacing = 1;
    if (value && (!toNumber(value.value(), spacing) || !std::isfinite(spacing) || spacing <= 0))
    {
      msg << "has " << size << "=\"" << value.value()
          << "\" in its OME-XML (a finite, positive number expected)";
      return msg.str();
    }
    const double scale = unit ? micrometres(unit.value()) : 1.0;
    if (scale == 0)
    {
      msg << "has " << size << "Unit=\"" << unit.value() << "\" in its OME-XML, a length unit "
          << "this reader does not know (pm, Å, nm, µm, mm, cm, dm, m)";
      return msg.str();
    }
    map.Spacing[a] = value ? spacing * scale : 1.0;
  }
  map.LengthUnit = "µm";

  // Times: TimeIncrement apart, in seconds; frame numbers without one.
  const pugi::xml_attribute increment = pixels.attribute("TimeIncrement");
  if (increment)
  {
    double dt = 0;
    const pugi::xml_attribute unit = pixels.attribute("TimeIncrementUnit");
    const double scale = unit ? seconds(unit.value()) : 1.0;
    if (!toNumber(increment.value(), dt) || !std::isfinite(dt) || dt <= 0)
    {
      msg << "has TimeIncrement=\"" << increment.value()
          << "\" in its OME-XML (a finite, positive number expected)";
      return msg.str();
    }
    if (scale == 0)
    {
      msg << "has TimeIncrementUnit=\"" << unit.value() << "\" in its OME-XML, a time unit "
          << "this reader does not know (ns, µs, ms, s, min, h)";
      return msg.str();
    }
    for (int t = 0; t < map.SizeT; ++t)
    {
      map.TimeValues[t] = t * dt * scale;
    }
    map.TimeUnit = "s";
  }

  // Channels: one per plane channel (SamplesPerPixel 1); their names.
  const std::vector<pugi::xml_node> channels = children(pixels, "Channel");
  if (!channels.empty())
  {
    if (channels.size() != sizes[3])
    {
      msg << "has SizeC=" << sizes[3] << " in its OME-XML but " << channels.size()
          << " Channel element" << (channels.size() == 1 ? "" : "s");
      return msg.str();
    }
    for (std::size_t c = 0; c < channels.size(); ++c)
    {
      const pugi::xml_attribute samples = channels[c].attribute("SamplesPerPixel");
      if (samples && samples.as_int() != 1)
      {
        msg << "has a Channel (number " << c + 1 << ") of SamplesPerPixel="
            << samples.value() << " (RGB planes), which this reader does not read";
        return msg.str();
      }
      map.ChannelNames[c] = channels[c].attribute("Name").value();
    }
    makeChannelNamesUnique(map.ChannelNames);
  }

  // Planes: TiffData blocks, each a run of planes in DimensionOrder from (FirstZ, FirstC,
  // FirstT), on consecutive pages from IFD. Without TiffData, the file's pages in order.
  const int extent[3] = { map.SizeZ, map.SizeC, map.SizeT };
  int dims[3]; // the plane axes, fastest first: 0 Z, 1 C, 2 T
  for (int i = 0; i < 3; ++i)
  {
    dims[i] = order[2 + i] == 'Z' ? 0 : order[2 + i] == 'C' ? 1 : 2;
  }
  const std::uint64_t total = sizes[2] * sizes[3] * sizes[4];
  auto planeIndex = [&](const int zct[3]) {
    return static_cast<std::uint64_t>(zct[dims[0]]) +
      static_cast<std::uint64_t>(extent[dims[0]]) *
      (zct[dims[1]] + static_cast<std::uint64_t>(extent[dims[1]]) * zct[dims[2]]);
  };
  map.Files.assign(1, fileName);
  std::vector<pugi::xml_node> blocks = children(pixels, "TiffData");
  const bool none = blocks.empty();
  for (std::size_t b = 0; b < (none ? 1 : blocks.size()); ++b)
  {
    const pugi::xml_node block = none ? pugi::xml_node() : blocks[b];
    double ifd = 0, count = 0, first[3] = { 0, 0, 0 };
    const char* firsts[3] = { "FirstZ", "FirstC", "FirstT" };
    const pugi::xml_attribute ifdAttr = block.attribute("IFD");
    const pugi::xml_attribute countAttr = block.attribute("PlaneCount");
    bool ok = (!ifdAttr || toNumber(ifdAttr.value(), ifd)) &&
      (!countAttr || toNumber(countAttr.value(), count));
    for (int i = 0; i < 3; ++i)
    {
      const pugi::xml_attribute a = block.attribute(firsts[i]);
      ok = ok && (!a || toNumber(a.value(), first[i])) && first[i] >= 0 &&
        first[i] == std::floor(first[i]) && first[i] < extent[i];
    }
    ok = ok && ifd >= 0 && ifd == std::floor(ifd) && ifd < 1e15 && count >= 0 &&
      count == std::floor(count) && (!countAttr || count >= 1);
    if (!ok)
    {
      msg << "has a TiffData (number " << b + 1 << ") in its OME-XML whose IFD, FirstZ, "
          << "FirstC, FirstT or PlaneCount is not a whole number within the Pixels' sizes";
      return msg.str();
    }
    const int zct[3] = { static_cast<int>(first[0]), static_cast<int>(first[1]),
      static_cast<int>(first[2]) };
    const std::uint64_t start = planeIndex(zct);
    // The OME schema: without PlaneCount, one plane when IFD is given, else all planes.
    std::uint64_t planes = countAttr ? static_cast<std::uint64_t>(count)
      : ifdAttr                      ? 1
                                     : total - start;
    if (start + planes > total)
    {
      msg << "has a TiffData (number " << b + 1 << ") in its OME-XML whose planes go past "
          << "the SizeZ x SizeC x SizeT = " << total << " planes of its Pixels";
      return msg.str();
    }
    int file = 0;
    const pugi::xml_node uuid = child(block, "UUID");
    const std::string other = uuid ? uuid.attribute("FileName").value() : "";
    if (!other.empty() && other != fileName)
    {
      file = -1;
      for (std::size_t f = 0; f < map.Files.size(); ++f)
      {
        file = map.Files[f] == other ? static_cast<int>(f) : file;
      }
      if (file < 0)
      {
        map.Files.push_back(other);
        file = static_cast<int>(map.Files.size()) - 1;
      }
    }
    for (std::uint64_t p = 0; p < planes; ++p)
    {
      const std::uint64_t i = start + p;
      int at[3];
      at[dims[0]] = static_cast<int>(i % extent[dims[0]]);
      at[dims[1]] = static_cast<int>((i / extent[dims[0]]) % extent[dims[1]]);
      at[dims[2]] = static_cast<int>(i / extent[dims[0]] / extent[dims[1]]);
      map.At(at[1], at[0], at[2]) = { file, static_cast<std::uint64_t>(ifd) + p };
    }
  }
  return "";
}

} // namespace mcv
