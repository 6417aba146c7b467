#include "TiffDirectories.h"

#include "vtksys/FStream.hxx"

#include <set>
#include <sstream>

namespace mcv
{
namespace
{
// A TIFF file opened for random reads of its directories. Classic TIFF: 2-byte entry
// counts, 12-byte entries, 4-byte offsets; BigTIFF: 8-byte counts, 20-byte entries, 8-byte
// offsets. Both byte orders.
class TiffFile
{
public:
  explicit TiffFile(const std::string& name)
    : In(name.c_str(), std::ios::in | std::ios::binary)
  {
    if (this->In)
    {
      this->In.seekg(0, std::ios::end);
      this->Size = static_cast<std::uint64_t>(this->In.tellg());
    }
  }

  bool Opened() const { return static_cast<bool>(this->In); }

  // Bytes [offset, offset + n) of the file; false when they are not all there.
  bool Read(std::uint64_t offset, std::size_t n, unsigned char* out)
  {
    if (offset > this->Size || n > this->Size - offset)
    {
      return false;
    }
    this->In.clear();
    this->In.seekg(static_cast<std::streamoff>(offset));
    return static_cast<bool>(this->In.read(reinterpret_cast<char*>(out), n));
  }

  std::uint64_t Number(const unsigned char* p, int bytes) const
  {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i)
    {
      const int k = this->BigEndian ? i : bytes - 1 - i;
      v = (v << 8) | p[k];
    }
    return v;
  }

  std::uint64_t Size = 0;
  bool BigEndian = false;
  bool Big = false; // BigTIFF

private:
  vtksys::ifstream In;
};

int typeBytes(std::uint64_t type)
{
  switch (type)
  {
    case 1: case 2: case 6: case 7: return 1; // BYTE ASCII SBYTE UNDEFINED
    case 3: case 8: return 2;                 // SHORT SSHORT
    case 4: case 9: case 11: case 13: return 4; // LONG SLONG FLOAT IFD
    case 5: case 10: case 12: case 16: case 17: case 18: return 8; // RATIONAL DOUBLE LONG8 ...
    default: return 0;
  }
}

// The integer values of one directory entry (inline or at its offset); false when they lie
// beyond the end of the file.
bool entryValues(TiffFile& file, const unsigned char* entry, std::vector<std::uint64_t>& values)
{
  const int countBytes = file.Big ? 8 : 4;
  const std::uint64_t type = file.Number(entry + 2, 2);
  const std::uint64_t count = file.Number(entry + 4, countBytes);
  const int size = typeBytes(type);
  values.clear();
  if (size == 0 || count == 0 || count > (std::uint64_t(1) << 26))
  {
    return true; // a type or count we do not use: no values
  }
  const unsigned char* inline_ = entry + 4 + countBytes;
  std::vector<unsigned char> bytes(static_cast<std::size_t>(count * size));
  if (bytes.size() <= static_cast<std::size_t>(countBytes))
  {
    std::copy(inline_, inline_ + bytes.size(), bytes.begin());
  }
  else if (!file.Read(file.Number(inline_, countBytes), bytes.size(), bytes.data()))
  {
    return false;
  }
  const int valueBytes = size == 8 && (type == 5 || type == 10) ? 4 : size; // rationals: numerators
  for (std::uint64_t i = 0; i < count; ++i)
  {
    values.push_back(file.Number(bytes.data() + i * size, valueBytes));
  }
  return true;
}

// The bytes of one directory entry (inline or at its offset); false when they lie beyond
// the end of the file.
bool rawEntryBytes(TiffFile& file, const unsigned char* entry, std::string& bytes)
{
  const int countBytes = file.Big ? 8 : 4;
  const std::uint64_t count = file.Number(entry + 4, countBytes);
  const int size = typeBytes(file.Number(entry + 2, 2));
  bytes.clear();
  if (size == 0 || count == 0 || count > (std::uint64_t(1) << 26))
  {
    return true;
  }
  const unsigned char* inline_ = entry + 4 + countBytes;
  bytes.resize(static_cast<std::size_t>(count * size));
  if (bytes.size() <= static_cast<std::size_t>(countBytes))
  {
    bytes.assign(reinterpret_cast<const char*>(inline_), bytes.size());
    return true;
  }
  return file.Read(file.Number(inline_, countBytes), bytes.size(),
    reinterpret_cast<unsigned char*>(&bytes[0]));
}

// A RATIONAL entry's first value; 0 when absent or its denominator is 0.
double rational(TiffFile& file, const std::string& bytes)
{
  if (bytes.size() < 8)
  {
    return 0;
  }
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  const double den = static_cast<double>(file.Number(p + 4, 4));
  return den == 0 ? 0 : static_cast<double>(file.Number(p, 4)) / den;
}
} // namespace

//------------------------------------------------------------------------------
bool startsLikeTiff(const std::string& name)
{
  TiffFile file(name);
  unsigned char head[4] = {};
  if (!file.Opened() || !file.Read(0, 4, head))
  {
    return false;
  }
  file.BigEndian = head[0] == 'M';
  const std::uint64_t magic = file.Number(head + 2, 2);
  return ((head[0] == 'I' && head[1] == 'I') || (head[0] == 'M' && head[1] == 'M')) &&
    (magic == 42 || magic == 43);
}

//------------------------------------------------------------------------------
std::string readTiffDirectories(const std::string& name, std::vector<TiffPage>& pages)
{
  pages.clear();
  TiffFile file(name);
  if (!file.Opened())
  {
    return "cannot be opened";
  }
  unsigned char head[16] = {};
  if (!startsLikeTiff(name))
  {
    return "is not a TIFF file (it does not start with a TIFF header)";
  }
  file.Read(0, 4, head);
  file.BigEndian = head[0] == 'M';
  file.Big = file.Number(head + 2, 2) == 43;
  if (!file.Read(0, file.Big ? 16 : 8, head))
  {
    return "is truncated: its TIFF header is cut short";
  }
  const int offsetBytes = file.Big ? 8 : 4;
  const int entryBytes = file.Big ? 20 : 12;
  std::uint64_t next = file.Number(head + (file.Big ? 8 : 4), offsetBytes);
  std::set<std::uint64_t> seen;
  std::ostringstream msg;
  while (next != 0)
  {
    const std::size_t page = pages.size() + 1;
    if (!seen.insert(next).second || pages.size() > 1000000)
    {
      msg << "has a loop in its chain of page directories (at page " << page << ")";
      return msg.str();
    }
    unsigned char countBuffer[8];
    std::vector<unsigned char> entries;
    std::uint64_t count = 0;
    bool whole = file.Read(next, file.Big ? 8 : 2, countBuffer);
    if (whole)
    {
      count = file.Number(countBuffer, file.Big ? 8 : 2);
      whole = count < 65536; // a count beyond this is garbage, not a directory
      if (whole)
      {
        entries.resize(static_cast<std::size_t>(count * entryBytes + offsetBytes));
        whole = file.Read(next + (file.Big ? 8 : 2), entries.size(), entries.data());
      }
    }
    if (!whole)
    {
      msg << "is truncated: the directory of page " << page << " starts at byte " << next
          << ", beyond its end (" << file.Size << " bytes)";
      return msg.str();
    }
    TiffPage p;
    std::vector<std::uint64_t> offsets, counts, values;
    for (std::uint64_t e = 0; e < count; ++e)
    {
      const unsigned char* entry = entries.data() + e * entryBytes;
      const std::uint64_t tag = file.Number(entry, 2);
      if (!entryValues(file, entry, values))
      {
        msg << "is truncated: tag " << tag << " of page " << page
            << " points beyond its end (" << file.Size << " bytes)";
        return msg.str();
      }
      const std::uint64_t first = values.empty() ? 0 : values[0];
      switch (tag)
      {
        case 256: p.Width = first; break;
        case 257: p.Height = first; break;
        case 258: p.BitsPerSample = static_cast<int>(first); break;
        case 259: p.Compression = static_cast<int>(first); break;
        case 277: p.SamplesPerPixel = static_cast<int>(first); break;
        case 339: p.SampleFormat = static_cast<int>(first); break;
        case 297: p.PageCount = values.size() > 1 ? static_cast<int>(values[1]) : 0; break;
        case 273: case 324: offsets = values; break; // strips or tiles
        case 279: case 325: counts = values; break;
        default: break;
      }
      const bool text = tag == 270 || tag == 282 || tag == 283 || tag == 50839;
      std::string bytes;
      if (pages.empty() && text)
      {
        if (!rawEntryBytes(file, entry, bytes))
        {
          msg << "is truncated: tag " << tag << " of page " << page
              << " points beyond its end (" << file.Size << " bytes)";
          return msg.str();
        }
        switch (tag)
        {
          case 270: p.Description = bytes.substr(0, bytes.find('\0')); break;
          case 282: p.XResolution = rational(file, bytes); break;
          case 283: p.YResolution = rational(file, bytes); break;
          default: p.IJMetadata = bytes; break;
        }
      }
      if (pages.empty() && tag == 50838)
      {
        p.IJMetadataByteCounts = values;
      }
    }
    p.BigEndian = file.BigEndian;
    p.DirectoryOffset = next;
    if (offsets.empty() || offsets.size() != counts.size())
    {
      msg << "has no usable image data on page " << page << " (" << offsets.size()
          << " strip offsets, " << counts.size() << " byte counts)";
      return msg.str();
    }
    for (std::size_t s = 0; s < offsets.size(); ++s)
    {
      if (offsets[s] > file.Size || counts[s] > file.Size - offsets[s])
      {
        msg << "is truncated: the image data of page " << page << " ends at byte "
            << offsets[s] + counts[s] << ", the file holds " << file.Size;
        return msg.str();
      }
      p.DataBytes += counts[s];
    }
    p.DataOffsets = offsets;
    pages.push_back(p);
    next = file.Number(entries.data() + count * entryBytes, offsetBytes);
  }
  return pages.empty() ? "has no pages" : "";
}

} // namespace mcv
