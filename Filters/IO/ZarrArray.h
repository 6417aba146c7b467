// One Zarr (format v2) array: its `.zarray` metadata and the decoding of its chunks.
// VTK-free apart from the JSON parser (VTK's jsoncpp) and zlib (VTK's); Blosc through
// Debian's libblosc. What vtkOMEZarrReader reads a resolution level of an OME-Zarr image with.
//
// Supported, as python3-zarr 2.x writes them: dtype u1 i1 u2 i2 u4 i4 u8 i8 f4 f8 in either
// byte order; order "C" or "F"; compressor null, blosc, zlib or gzip; filters null;
// dimension_separator "." or "/". Anything else is refused with a message that names it.
#ifndef ZarrArray_h
#define ZarrArray_h

#include <cstdint> // for std::int64_t
#include <string>  // for std::string
#include <vector>  // for std::vector

namespace mcv
{
namespace zarr
{

enum class Codec
{
  None,
  Blosc,
  Zlib,
  Gzip
};

struct ArrayMeta
{
  std::vector<std::int64_t> Shape;
  std::vector<std::int64_t> Chunks;
  std::string DType;     // as written, e.g. "<u2"
  char Kind = 'u';       // 'u' unsigned, 'i' signed integer, 'f' floating point
  int ItemSize = 1;      // bytes per element
  bool BigEndian = false;
  bool FortranOrder = false;
  Codec Compressor = Codec::None;
  std::string CompressorId; // "blosc", "zlib", "gzip" or "" for none
  double FillValue = 0; // null in the file: 0 (the spec leaves it undefined)
  std::string Separator = ".";

  // Elements of one (full) chunk.
  std::int64_t ChunkElements() const;
  // Chunks along `axis`: ceil(Shape / Chunks).
  std::int64_t ChunksAlong(int axis) const;
};

// Parses the text of a `.zarray` file. Returns "" on success, else the problem (e.g.
// "has dtype '<c8' (complex numbers), which cannot be read").
std::string parseArrayMeta(const std::string& text, ArrayMeta& meta);

// The key of the chunk at grid position `index`, e.g. "0.1.2" or "0/1/2".
std::string chunkKey(const std::vector<std::int64_t>& index, const std::string& separator);

// Decodes the stored bytes of one chunk into `out` (ChunkElements() * ItemSize bytes, in
// the file's byte order and element order). Returns "" on success, else the problem (a
// stream that does not decode, or one that decodes to the wrong number of bytes).
std::string decodeChunk(
  const ArrayMeta& meta, const std::vector<char>& stored, std::vector<char>& out);

// Reverses the bytes of each of the `count` elements of `itemSize` bytes at `data`.
void swapBytes(char* data, std::int64_t count, int itemSize);

// True when this machine stores numbers little-endian.
bool hostIsLittleEndian();

// Reads a whole file into `bytes`; false when it cannot be opened or read.
bool readFile(const std::string& name, std::vector<char>& bytes);

} // namespace zarr
} // namespace mcv

#endif
