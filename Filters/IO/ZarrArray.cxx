#include "ZarrArray.h"

#include "vtk_jsoncpp.h"
#include "vtk_zlib.h"
#include "vtksys/FStream.hxx"

#include "../Common/mcvJsonObject.h"

#include <blosc.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace mcv
{
namespace zarr
{
namespace
{
// A JSON value on one line, for messages.
std::string compact(const Json::Value& value)
{
  Json::StreamWriterBuilder builder;
  builder["indentation"] = "";
  return Json::writeString(builder, value).substr(0, 80);
}

// What a dtype's kind letter means, for the messages about those that cannot be read.
std::string kindName(char kind)
{
  switch (kind)
  {
    case 'b':
      return "booleans";
    case 'c':
      return "complex numbers";
    case 'O':
      return "Python objects";
    case 'S':
    case 'a':
      return "byte strings";
    case 'U':
      return "text";
    case 'M':
      return "dates";
    case 'm':
      return "time differences";
    case 'V':
      return "raw records";
    default:
      return "an unknown kind";
  }
}

std::string parseDType(const Json::Value& dtype, ArrayMeta& meta)
{
  if (!dtype.isString())
  {
    return "has a structured dtype (a list of fields), which cannot be read: one number per "
           "element is needed";
  }
  const std::string d = dtype.asString();
  meta.DType = d;
  const std::string readable = "; u1 i1 u2 i2 u4 i4 u8 i8 f4 f8 (either byte order) can be read";
  if (d.size() < 2 || (d[0] != '<' && d[0] != '>' && d[0] != '|'))
  {
    return "has dtype '" + d + "', which is not a NumPy type string" + readable;
  }
  const char kind = d[1];
  if (kind != 'u' && kind != 'i' && kind != 'f')
  {
    return "has dtype '" + d + "' (" + kindName(kind) + "), which cannot be read" + readable;
  }
  int size = 0;
  try
  {
    size = std::stoi(d.substr(2));
  }
  catch (...)
  {
    size = 0;
  }
  const bool ok = (kind == 'f' && (size == 4 || size == 8)) ||
    (kind != 'f' && (size == 1 || size == 2 || size == 4 || size == 8));
  if (!ok || d.size() != 3)
  {
    return "has dtype '" + d + "', which cannot be read" + readable;
  }
  meta.Kind = kind;
  meta.ItemSize = size;
  meta.BigEndian = d[0] == '>' && size > 1;
  return "";
}

std::string parseFill(const Json::Value& fill, ArrayMeta& meta)
{
  if (fill.isNull())
  {
    meta.FillValue = 0;
  }
  else if (fill.isNumeric())
  {
    meta.FillValue = fill.asDouble();
  }
  else if (fill.isString() && fill.asString() == "NaN")
  {
    meta.FillValue = std::numeric_limits<double>::quiet_NaN();
  }
  else if (fill.isString() && fill.asString() == "Infinity")
  {
    meta.FillValue = std::numeric_limits<double>::infinity();
  }
  else if (fill.isString() && fill.asString() == "-Infinity")
  {
    meta.FillValue = -std::numeric_limits<double>::infinity();
  }
  else
  {
    return "has a fill_value (" + compact(fill) + ") that is not a number";
  }
  if (meta.Kind != 'f' && !std::isfinite(meta.FillValue))
  {
    return "has a fill_value that is not finite for the integer dtype '" + meta.DType + "'";
  }
  return "";
}

std::string parseCompressor(const Json::Value& compressor, ArrayMeta& meta)
{
  if (compressor.isNull())
  {
    meta.Compressor = Codec::None;
    meta.CompressorId.clear();
    return "";
  }
  if (!compressor.isObject() || !compressor["id"].isString())
  {
    return "has a compressor without an id";
  }
  const std::string id = compressor["id"].asString();
  meta.CompressorId = id;
  if (id == "blosc")
  {
    meta.Compressor = Codec::Blosc;
  }
  else if (id == "zlib")
  {
    meta.Compressor = Codec::Zlib;
  }
  else if (id == "gzip")
  {
    meta.Compressor = Codec::Gzip;
  }
  else
  {
    return "is compressed with '" + id +
      "', which cannot be read (null, blosc, zlib and gzip can be read)";
  }
  return "";
}

// A list of positive integers, `what` naming it in the message.
std::string parseSizes(
  const Json::Value& value, const char* what, std::vector<std::int64_t>& sizes, bool positive)
{
  sizes.clear();
  if (!value.isArray() || value.empty())
  {
    return std::string("has no ") + what + " (a list of sizes)";
  }
  for (const Json::Value& v : value)
  {
    if (!v.isIntegral() || v.asInt64() < (positive ? 1 : 0))
    {
      return std::string("has ") + what + " " + compact(value) +
        " with an entry that is not a " + (positive ? "positive" : "non-negative") + " integer";
    }
    sizes.push_back(v.asInt64());
  }
  return "";
}

// Inflates a zlib or gzip stream into exactly out.size() bytes.
std::string inflateInto(const std::vector<char>& stored, std::vector<char>& out, Codec codec)
{
  const bool gzip = stored.size() >= 2 && static_cast<unsigned char>(stored[0]) == 0x1f &&
    static_cast<unsigned char>(stored[1]) == 0x8b;
  if ((codec == Codec::Gzip) != gzip)
  {
    return codec == Codec::Gzip ? "does not start as a gzip stream"
                                : "starts as a gzip stream, but .zarray says zlib";
  }
  z_stream zs{};
  if (inflateInit2(&zs, codec == Codec::Gzip ? 15 + 16 : 15) != Z_OK)
  {
    return "cannot be decompressed (zlib could not start)";
  }
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(stored.data()));
  zs.avail_in = static_cast<uInt>(stored.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  int code = inflate(&zs, Z_FINISH);
  const std::size_t produced = out.size() - zs.avail_out;
  std::string problem;
  if (code == Z_STREAM_END)
  {
    if (produced != out.size())
    {
      problem = "decompresses to " + std::to_string(produced) + " bytes instead of the " +
        std::to_string(out.size()) + " of a chunk";
    }
  }
  else if (code == Z_BUF_ERROR && zs.avail_out == 0)
  {
    // Output full but the stream goes on: more data than a chunk holds.
    unsigned char spare[1];
    zs.next_out = spare;
    zs.avail_out = 1;
    code = inflate(&zs, Z_FINISH);
    problem = "decompresses to more than the " + std::to_string(out.size()) +
      " bytes of a chunk";
  }
  else
  {
    problem = std::string("is not a valid ") + (gzip ? "gzip" : "zlib") + " stream (" +
      (zs.msg ? zs.msg : "truncated") + ")";
  }
  inflateEnd(&zs);
  return problem;
}
} // namespace

//------------------------------------------------------------------------------
std::int64_t ArrayMeta::ChunkElements() const
{
  std::int64_t n = 1;
  for (std::int64_t c : this->Chunks)
  {
    n *= c;
  }
  return n;
}

//------------------------------------------------------------------------------
std::int64_t ArrayMeta::ChunksAlong(int axis) const
{
  return (this->Shape[axis] + this->Chunks[axis] - 1) / this->Chunks[axis];
}

//------------------------------------------------------------------------------
std::string parseArrayMeta(const std::string& text, ArrayMeta& meta)
{
  Json::Value root;
  std::string why;
  if (!mcv::vtkhelpers::parseJsonObject(text, root, why))
  {
    return "is not valid JSON (" + why + ")";
  }
  if (!root["zarr_format"].isIntegral() || root["zarr_format"].asInt() != 2)
  {
    return "is not Zarr format 2 (its zarr_format is missing or not 2)";
  }
  std::string problem = parseSizes(root["shape"], "shape", meta.Shape, true);
  if (problem.empty())
  {
    problem = parseSizes(root["chunks"], "chunks", meta.Chunks, true);
  }
  if (!problem.empty())
  {
    return problem;
  }
  if (meta.Chunks.size() != meta.Shape.size())
  {
    return "has " + std::to_string(meta.Chunks.size()) + " chunk sizes for a shape of " +
      std::to_string(meta.Shape.size()) + " dimensions";
  }
  problem = parseDType(root["dtype"], meta);
  if (problem.empty())
  {
    problem = parseFill(root["fill_value"], meta);
  }
  if (problem.empty())
  {
    problem = parseCompressor(root["compressor"], meta);
  }
  if (!problem.empty())
  {
    return problem;
  }
  const Json::Value& order = root["order"];
  if (!order.isString() || (order.asString() != "C" && order.asString() != "F"))
  {
    return "has order " + compact(order) + " (\"C\" or \"F\" can be read)";
  }
  meta.FortranOrder = order.asString() == "F";
  const Json::Value& filters = root["filters"];
  if (!filters.isNull() && !(filters.isArray() && filters.empty()))
  {
    std::string ids;
    for (const Json::Value& f : filters)
    {
      ids += (ids.empty() ? "" : ", ") + (f["id"].isString() ? f["id"].asString() : "?");
    }
    return "has filters (" + ids + "), which cannot be read (filters must be null)";
  }
  const Json::Value& separator = root["dimension_separator"];
  meta.Separator = separator.isString() ? separator.asString() : ".";
  if (meta.Separator != "." && meta.Separator != "/")
  {
    return "has dimension_separator '" + meta.Separator + "' (\".\" or \"/\" can be read)";
  }
  // The bytes of one chunk must be addressable and fit one zlib call (uInt).
  double chunkBytes = static_cast<double>(meta.ItemSize);
  for (std::int64_t c : meta.Chunks)
  {
    chunkBytes *= static_cast<double>(c);
  }
  if (chunkBytes > static_cast<double>(std::numeric_limits<unsigned int>::max()))
  {
    return "has chunks of " + std::to_string(static_cast<long long>(chunkBytes)) +
      " bytes, more than 4 GiB";
  }
  return "";
}

//------------------------------------------------------------------------------
std::string chunkKey(const std::vector<std::int64_t>& index, const std::string& separator)
{
  std::string key;
  for (std::size_t i = 0; i < index.size(); ++i)
  {
    key += (i ? separator : std::string()) + std::to_string(index[i]);
  }
  return key;
}

//------------------------------------------------------------------------------
std::string decodeChunk(
  const ArrayMeta& meta, const std::vector<char>& stored, std::vector<char>& out)
{
  const std::size_t expected = static_cast<std::size_t>(meta.ChunkElements()) * meta.ItemSize;
  out.resize(expected);
  switch (meta.Compressor)
  {
    case Codec::None:
      if (stored.size() != expected)
      {
        return "holds " + std::to_string(stored.size()) + " bytes instead of the " +
          std::to_string(expected) + " of an uncompressed chunk";
      }
      std::copy(stored.begin(), stored.end(), out.begin());
      return "";
    case Codec::Blosc:
    {
      std::size_t nbytes = 0;
      if (stored.size() < BLOSC_MIN_HEADER_LENGTH ||
        blosc_cbuffer_validate(stored.data(), stored.size(), &nbytes) < 0)
      {
        return "is not a valid Blosc buffer (" + std::to_string(stored.size()) + " bytes)";
      }
      if (nbytes != expected)
      {
        return "decompresses to " + std::to_string(nbytes) + " bytes instead of the " +
          std::to_string(expected) + " of a chunk";
      }
      // The _ctx variant keeps no global state: readers may run in several threads.
      const int n = blosc_decompress_ctx(stored.data(), out.data(), out.size(), 1);
      if (n < 0 || static_cast<std::size_t>(n) != expected)
      {
        return "cannot be decompressed by Blosc (code " + std::to_string(n) + ")";
      }
      return "";
    }
    case Codec::Zlib:
    case Codec::Gzip:
      return inflateInto(stored, out, meta.Compressor);
  }
  return "has an unknown compressor";
}

//------------------------------------------------------------------------------
void swapBytes(char* data, std::int64_t count, int itemSize)
{
  for (std::int64_t i = 0; i < count; ++i)
  {
    std::reverse(data + i * itemSize, data + (i + 1) * itemSize);
  }
}

//------------------------------------------------------------------------------
bool hostIsLittleEndian()
{
  const std::uint16_t one = 1;
  return *reinterpret_cast<const unsigned char*>(&one) == 1;
}

//------------------------------------------------------------------------------
bool readFile(const std::string& name, std::vector<char>& bytes)
{
  vtksys::ifstream in(name.c_str(), std::ios::in | std::ios::binary);
  if (!in)
  {
    return false;
  }
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0)
  {
    return false;
  }
  in.seekg(0, std::ios::beg);
  bytes.resize(static_cast<std::size_t>(size));
  return size == 0 || static_cast<bool>(in.read(bytes.data(), size));
}

} // namespace zarr
} // namespace mcv
