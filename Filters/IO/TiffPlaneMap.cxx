#include "TiffPlaneMap.h"

#include <set>
#include <sstream>

namespace mcv
{

//------------------------------------------------------------------------------
bool TiffPlaneMap::Allocate()
{
  if (this->SizeZ < 1 || this->SizeC < 1 || this->SizeT < 1 ||
    static_cast<double>(this->SizeZ) * this->SizeC * this->SizeT > 2147483647.0)
  {
    return false;
  }
  this->Planes.assign(static_cast<std::size_t>(this->SizeZ) * this->SizeC * this->SizeT, {});
  this->TimeValues.clear();
  for (int t = 0; t < this->SizeT; ++t)
  {
    this->TimeValues.push_back(t);
  }
  this->TimeUnit = "frame";
  this->ChannelNames.clear();
  for (int c = 0; c < this->SizeC; ++c)
  {
    this->ChannelNames.push_back("C" + std::to_string(c + 1));
  }
  return true;
}

//------------------------------------------------------------------------------
TiffPlaneRef& TiffPlaneMap::At(int c, int z, int t)
{
  return this->Planes[(static_cast<std::size_t>(t) * this->SizeZ + z) * this->SizeC + c];
}

//------------------------------------------------------------------------------
const TiffPlaneRef& TiffPlaneMap::At(int c, int z, int t) const
{
  return this->Planes[(static_cast<std::size_t>(t) * this->SizeZ + z) * this->SizeC + c];
}

//------------------------------------------------------------------------------
std::string checkPlaneMap(const TiffPlaneMap& map, const std::vector<std::uint64_t>& pageCounts)
{
  for (int t = 0; t < map.SizeT; ++t)
  {
    for (int z = 0; z < map.SizeZ; ++z)
    {
      for (int c = 0; c < map.SizeC; ++c)
      {
        const TiffPlaneRef& ref = map.At(c, z, t);
        std::ostringstream msg;
        if (ref.File < 0 || ref.File >= static_cast<int>(map.Files.size()))
        {
          msg << "has no page for channel " << c + 1 << ", slice " << z + 1 << ", frame "
              << t + 1 << " (its " << map.Format << " metadata maps no page there)";
          return msg.str();
        }
        const std::uint64_t pages =
          ref.File < static_cast<int>(pageCounts.size()) ? pageCounts[ref.File] : 0;
        if (ref.Page >= pages)
        {
          msg << "has its plane for channel " << c + 1 << ", slice " << z + 1 << ", frame "
              << t + 1 << " on page " << ref.Page + 1 << " of '" << map.Files[ref.File]
              << "', which holds " << pages << " pages";
          return msg.str();
        }
      }
    }
  }
  return "";
}

//------------------------------------------------------------------------------
void makeChannelNamesUnique(std::vector<std::string>& names)
{
  std::set<std::string> used;
  for (std::size_t c = 0; c < names.size(); ++c)
  {
    std::string name = names[c];
    if (name.empty() || used.count(name))
    {
      name = "C" + std::to_string(c + 1);
    }
    for (int k = 2; used.count(name); ++k)
    {
      name = "C" + std::to_string(c + 1) + "_" + std::to_string(k);
    }
    used.insert(name);
    names[c] = name;
  }
}

} // namespace mcv
