#include "ImageJHyperstack.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

namespace mcv
{
namespace
{
// key=value lines of the description (ImageJ writes one per line, no quoting).
std::map<std::string, std::string> keyValues(const std::string& description)
{
  std::map<std::string, std::string> values;
  std::istringstream lines(description);
  std::string line;
  while (std::getline(lines, line))
  {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
    {
      line.pop_back();
    }
    const std::size_t eq = line.find('=');
    if (eq != std::string::npos && eq > 0)
    {
      values[line.substr(0, eq)] = line.substr(eq + 1);
    }
  }
  return values;
}

// A whole-string number; false when the text is not one.
bool toNumber(const std::string& text, double& value)
{
  if (text.empty())
  {
    return false;
  }
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end && *end == '\0';
}

// ImageJ's length unit names (Calibration.setUnit accepts these spellings; "\u00B5m" is
// how ImageJ escapes µ in the description) -> the unit reported; "" when unknown.
std::string lengthUnit(const std::string& unit)
{
  static const std::map<std::string, std::string> units = { { "pixel", "pixel" },
    { "pixels", "pixel" }, { "nm", "nm" }, { "nanometer", "nm" }, { "um", "µm" },
    { "µm", "µm" }, { "\xb5m", "µm" }, { "\\u00B5m", "µm" }, { "\\u00b5m", "µm" },
    { "micron", "µm" }, { "microns", "µm" }, { "micrometer", "µm" }, { "mm", "mm" },
    { "millimeter", "mm" }, { "cm", "cm" }, { "centimeter", "cm" }, { "m", "m" },
    { "meter", "m" }, { "inch", "inch" }, { "inches", "inch" }, { "A", "Å" }, { "Å", "Å" },
    { "angstrom", "Å" } };
  const auto found = units.find(unit);
  return found == units.end() ? "" : found->second;
}

// UTF-16 code units (of the given byte order) -> UTF-8.
std::string utf8(const std::string& bytes, bool bigEndian)
{
  std::string out;
  for (std::size_t i = 0; i + 1 < bytes.size(); i += 2)
  {
    const unsigned a = static_cast<unsigned char>(bytes[i]);
    const unsigned b = static_cast<unsigned char>(bytes[i + 1]);
    unsigned u = bigEndian ? (a << 8 | b) : (b << 8 | a);
    if (u >= 0xd800 && u < 0xe000)
    {
      u = 0xfffd; // a surrogate pair: labels are names, not emoji; a replacement char
    }
    if (u < 0x80)
    {
      out += static_cast<char>(u);
    }
    else if (u < 0x800)
    {
      out += static_cast<char>(0xc0 | (u >> 6));
      out += static_cast<char>(0x80 | (u & 0x3f));
    }
    else
    {
      out += static_cast<char>(0xe0 | (u >> 12));
      out += static_cast<char>(0x80 | ((u >> 6) & 0x3f));
      out += static_cast<char>(0x80 | (u & 0x3f));
    }
  }
  return out;
}
} // namespace

//------------------------------------------------------------------------------
bool isImageJDescription(const std::string& description)
{
  return description.compare(0, 7, "ImageJ=") == 0;
}

//------------------------------------------------------------------------------
std::vector<std::string> imageJLabels(const ImageJTags& tags)
{
  // IJMetadata: a header of a magic "IJIJ" (4 bytes, in the file's byte order) and
  // (type, count) pairs of 4-byte values, then one entry per IJMetadataByteCounts value
  // after the first (the header's); "labl" entries are the slice labels.
  std::vector<std::string> labels;
  const std::string& m = tags.Metadata;
  const std::vector<std::uint64_t>& counts = tags.MetadataByteCounts;
  auto number = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
    {
      const int k = tags.BigEndian ? i : 3 - i;
      v = (v << 8) | static_cast<unsigned char>(m[at + k]);
    }
    return v;
  };
  if (counts.empty() || m.size() < 4 || counts[0] < 4 || counts[0] > m.size() ||
    number(0) != 0x494a494a) // "IJIJ"
  {
    return labels;
  }
  std::size_t entry = 1;
  std::size_t at = counts[0];
  for (std::size_t h = 4; h + 8 <= counts[0]; h += 8)
  {
    const std::uint32_t type = number(h);
    const std::uint32_t n = number(h + 4);
    for (std::uint32_t i = 0; i < n; ++i, ++entry)
    {
      if (entry >= counts.size() || counts[entry] > m.size() - at)
      {
        return {};
      }
      if (type == 0x6c61626c) // "labl"
      {
        labels.push_back(utf8(m.substr(at, counts[entry]), tags.BigEndian));
      }
      at += counts[entry];
    }
  }
  return labels;
}

//------------------------------------------------------------------------------
std::string parseImageJ(const ImageJTags& tags, std::uint64_t pages, TiffPlaneMap& map)
{
  const std::map<std::string, std::string> v = keyValues(tags.Description);
  std::ostringstream msg;
  // A count: a positive whole number, `fallback` when the key is absent.
  auto count = [&](const char* key, double fallback, double& value) {
    const auto found = v.find(key);
    value = fallback;
    if (found == v.end())
    {
      return true;
    }
    if (!toNumber(found->second, value) || value < 1 || value != std::floor(value) ||
      value > 2147483647.0)
    {
      msg << "has " << key << "=" << found->second
          << " in its ImageJ description (a whole number of at least 1 expected)";
      return false;
    }
    return true;
  };
  double images = 0, channels = 0, frames = 0, slices = 0;
  if (!count("images", static_cast<double>(pages), images) || !count("channels", 1, channels) ||
    !count("frames", 1, frames))
  {
    return msg.str();
  }
  // Without slices=, ImageJ takes the images that the channels and frames leave.
  const double fallbackSlices = std::floor(images / (channels * frames));
  if (!count("slices", fallbackSlices >= 1 ? fallbackSlices : 1, slices))
  {
    return msg.str();
  }
  if (images != channels * slices * frames)
  {
    msg << "has images=" << images << " in its ImageJ description, but channels=" << channels
        << " x slices=" << slices << " x frames=" << frames << " = "
        << channels * slices * frames;
    return msg.str();
  }
  if (images > static_cast<double>(pages))
  {
    msg << "is missing pages: its ImageJ description counts images=" << images
        << ", the file holds " << pages << " page" << (pages == 1 ? "" : "s");
    return msg.str();
  }
  map.Format = "ImageJ hyperstack";
  map.SizeC = static_cast<int>(channels);
  map.SizeZ = static_cast<int>(slices);
  map.SizeT = static_cast<int>(frames);
  if (!map.Allocate())
  {
    msg << "has channels=" << channels << " x slices=" << slices << " x frames=" << frames
        << " planes, more than this reader can index";
    return msg.str();
  }
  std::uint64_t page = 0;
  for (int t = 0; t < map.SizeT; ++t)
  {
    for (int z = 0; z < map.SizeZ; ++z)
    {
      for (int c = 0; c < map.SizeC; ++c)
      {
        map.At(c, z, t) = { 0, page++ };
      }
    }
  }

  // Spacing: X and Y from the resolution (pixels per unit), Z from spacing=.
  const auto unit = v.find("unit");
  map.LengthUnit = unit == v.end() ? "pixel" : lengthUnit(unit->second);
  if (map.LengthUnit.empty())
  {
    msg << "has unit=" << unit->second << " in its ImageJ description, a length unit this "
        << "reader does not know (pixel, nm, um or micron, mm, cm, m, inch, A)";
    return msg.str();
  }
  const double xres = tags.XResolution;
  const double yres = tags.YResolution > 0 ? tags.YResolution : xres;
  map.Spacing[0] = xres > 0 && std::isfinite(xres) ? 1.0 / xres : 1.0;
  map.Spacing[1] = yres > 0 && std::isfinite(yres) ? 1.0 / yres : 1.0;
  map.Spacing[2] = 1;
  const auto spacing = v.find("spacing");
  if (spacing != v.end() &&
    (!toNumber(spacing->second, map.Spacing[2]) || !std::isfinite(map.Spacing[2]) ||
      map.Spacing[2] == 0))
  {
    msg << "has spacing=" << spacing->second
        << " in its ImageJ description (a finite, non-zero number expected)";
    return msg.str();
  }

  // Frames: finterval= apart, in tunit= (ImageJ's default: seconds).
  const auto finterval = v.find("finterval");
  if (finterval != v.end())
  {
    double dt = 0;
    if (!toNumber(finterval->second, dt) || !std::isfinite(dt) || dt <= 0)
    {
      msg << "has finterval=" << finterval->second
          << " in its ImageJ description (a finite, positive number expected)";
      return msg.str();
    }
    for (int t = 0; t < map.SizeT; ++t)
    {
      map.TimeValues[t] = t * dt;
    }
    const auto tunit = v.find("tunit");
    map.TimeUnit = tunit == v.end() || tunit->second.empty() ? "s" : tunit->second;
  }

  // Channel names: the labels of the first C planes (frame 1, slice 1), ImageJ's slice
  // labels of a hyperstack; or as many labels as channels.
  const std::vector<std::string> labels = imageJLabels(tags);
  if (labels.size() == static_cast<std::size_t>(images) ||
    labels.size() == static_cast<std::size_t>(map.SizeC))
  {
    bool any = false;
    for (int c = 0; c < map.SizeC; ++c)
    {
      any = any || !labels[c].empty();
    }
    if (any)
    {
      map.ChannelNames.assign(labels.begin(), labels.begin() + map.SizeC);
      makeChannelNamesUnique(map.ChannelNames);
    }
  }
  return "";
}

} // namespace mcv
