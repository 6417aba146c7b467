#include "mcvReductionModelFile.h"

#include "vtk_jsoncpp.h"
#include "vtk_zlib.h"

#include "../Common/mcvJsonObject.h"

#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace mcv
{
namespace vtkhelpers
{

namespace
{
const char kMagic[8] = { 'M', 'C', 'V', 'M', 'O', 'D', 'E', 'L' };

void putU32(std::vector<char>& out, std::uint32_t v)
{
  for (int i = 0; i < 4; ++i)
  {
    out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
  }
}

std::uint32_t getU32(const char* p)
{
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i)
  {
    v |= static_cast<std::uint32_t>(static_cast<unsigned char>(p[i])) << (8 * i);
  }
  return v;
}

std::uint32_t crcOf(const char* p, std::size_t n)
{
  uLong crc = crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths: feed it in pieces.
  while (n > 0)
  {
    const uInt piece = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(p), piece);
    p += piece;
    n -= piece;
  }
  return static_cast<std::uint32_t>(crc);
}

// The scalar fields kept under a fixed key of the selection and fit sections: one list that
// encodeModel and decodeModel both walk, so that a field is named in one place.
enum Section
{
  SelectionSection,
  FitSection
};
template <class Model, class Visit>
void visitScalarFields(Model& m, Visit visit)
{
  auto& s = m.features.selection;
  visit(SelectionSection, "intensity", s.intensity);
  visit(SelectionSection, "gradient", s.gradient);
  visit(SelectionSection, "gradientMagnitude", s.gradientMagnitude);
  visit(SelectionSection, "laplacian", s.laplacian);
  visit(SelectionSection, "localMean", s.localMean);
  visit(SelectionSection, "localVariance", s.localVariance);
  visit(FitSection, "numberOfNeighbors", m.fit.numberOfNeighbors);
  visit(FitSection, "numberOfLandmarks", m.fit.numberOfLandmarks);
  visit(FitSection, "numberOfEpochs", m.fit.numberOfEpochs);
  visit(FitSection, "minimumDistance", m.fit.minimumDistance);
  visit(FitSection, "referenceSampleSize", m.fit.referenceSampleSize);
  visit(FitSection, "randomSeed", m.fit.randomSeed);
  visit(FitSection, "sampledVoxels", m.fit.sampledVoxels);
  visit(FitSection, "fittedOn", m.fit.fittedOn);
}

Json::Value jsonOf(bool v)
{
  return Json::Value(v);
}
Json::Value jsonOf(int v)
{
  return Json::Value(v);
}
Json::Value jsonOf(double v)
{
  return Json::Value(v);
}
Json::Value jsonOf(std::uint64_t v)
{
  return Json::Value(static_cast<Json::UInt64>(v));
}
Json::Value jsonOf(const std::string& v)
{
  return Json::Value(v);
}

void fromJson(const Json::Value& j, bool& v)
{
  v = j.asBool();
}
void fromJson(const Json::Value& j, int& v)
{
  v = j.asInt();
}
void fromJson(const Json::Value& j, double& v)
{
  v = j.asDouble();
}
void fromJson(const Json::Value& j, std::uint64_t& v)
{
  v = j.asUInt64();
}
void fromJson(const Json::Value& j, std::string& v)
{
  v = j.asString();
}

// The hosts this suite runs on are little-endian (x86-64, aarch64); the file is too.
bool littleEndian()
{
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

Json::Value stringList(const std::vector<std::string>& values)
{
  Json::Value list(Json::arrayValue);
  for (const std::string& v : values)
  {
    list.append(v);
  }
  return list;
}

template <class T>
Json::Value numberList(const std::vector<T>& values)
{
  Json::Value list(Json::arrayValue);
  for (const T& v : values)
  {
    list.append(v);
  }
  return list;
}

// A binary block: its name, element type and the bytes.
struct Block
{
  std::string name, type;
  std::size_t count = 0;
  const void* data = nullptr;
  std::size_t elementSize() const { return type == "float64" ? 8 : 4; }
};

std::vector<Block> blocksOf(const ModelFile& m)
{
  const ReductionModel& r = m.reduction;
  return {
    { "referenceFeatures", "float32", r.referenceFeatures.size(), r.referenceFeatures.data() },
    { "referenceCoordinates", "float32", r.referenceCoordinates.size(), r.referenceCoordinates.data() },
    { "pcaMean", "float64", r.pcaMean.size(), r.pcaMean.data() },
    { "pcaAxes", "float64", r.pcaAxes.size(), r.pcaAxes.data() },
  };
}

// The elements of the JSON array `v` into `out`, each converted by `as` (Value::asString,
// ...); false when `v` is no array or an element fails `is` (Value::isString, ...).
template <class T, class Converted>
bool readArray(const Json::Value& v, bool (Json::Value::*is)() const,
  Converted (Json::Value::*as)() const, std::vector<T>& out)
{
  if (!v.isArray())
  {
    return false;
  }
  out.clear();
  for (const Json::Value& element : v)
  {
    if (!(element.*is)())
    {
      return false;
    }
    out.push_back((element.*as)());
  }
  return true;
}

bool readStrings(const Json::Value& v, std::vector<std::string>& out)
{
  return readArray(v, &Json::Value::isString, &Json::Value::asString, out);
}

bool readDoubles(const Json::Value& v, std::vector<double>& out)
{
  return readArray(v, &Json::Value::isNumeric, &Json::Value::asDouble, out);
}

} // namespace

std::vector<char> encodeModel(const ModelFile& m)
{
  const FeatureRecipe& f = m.features;
  const ReductionModel& r = m.reduction;
  Json::Value root(Json::objectValue);
  root["format"] = "Multichannel Explorer reduction model";
  Json::Value features(Json::objectValue);
  features["channels"] = stringList(f.channels);
  features["featureSet"] = presetName(f.preset);
  Json::Value selection(Json::objectValue);
  Json::Value fit(Json::objectValue);
  Json::Value* sections[] = { &selection, &fit };
  visitScalarFields(m, [&](Section section, const char* key, const auto& field)
    { (*sections[section])[key] = jsonOf(field); });
  features["selection"] = selection;
  features["normalization"] = normalizationName(f.normalization);
  features["names"] = stringList(f.featureNames);
  features["offset"] = numberList(f.offset);
  features["scale"] = numberList(f.scale);
  features["spacing"] = numberList(std::vector<double>(f.spacing.begin(), f.spacing.end()));
  features["lengthUnit"] = f.lengthUnit;
  features["maskBackground"] = f.maskBackground;
  features["backgroundThreshold"] = f.backgroundThreshold;
  root["features"] = features;

  Json::Value reduction(Json::objectValue);
  reduction["method"] = reductionMethodName(r.method);
  reduction["outputDimension"] = r.outputDimension;
  reduction["featureColumns"] = r.featureColumns;
  reduction["usedColumns"] = numberList(r.usedColumns);
  reduction["references"] = static_cast<Json::UInt64>(r.references);
  reduction["referenceRadius"] = r.referenceRadius;
  reduction["eigenvalues"] = numberList(r.eigenvalues);
  reduction["varianceRetained"] = r.varianceRetained;
  // NaN (not measured) is not JSON: null.
  reduction["trustworthiness"] = std::isfinite(r.trustworthiness) ? Json::Value(r.trustworthiness) : Json::Value();
  root["reduction"] = reduction;

  fit["volumeDimensions"] = numberList(std::vector<int>(m.fit.volumeDimensions.begin(), m.fit.volumeDimensions.end()));
  root["fit"] = fit;

  Json::Value blocks(Json::arrayValue);
  for (const Block& b : blocksOf(m))
  {
    Json::Value entry(Json::objectValue);
    entry["name"] = b.name;
    entry["type"] = b.type;
    entry["count"] = static_cast<Json::UInt64>(b.count);
    blocks.append(entry);
  }
  root["blocks"] = blocks;

  Json::StreamWriterBuilder writer;
  writer["indentation"] = " ";
  writer["precision"] = 17; // doubles round-trip
  const std::string header = Json::writeString(writer, root);

  std::vector<char> out(kMagic, kMagic + 8);
  putU32(out, kModelFormatVersion);
  putU32(out, static_cast<std::uint32_t>(header.size()));
  out.insert(out.end(), header.begin(), header.end());
  for (const Block& b : blocksOf(m))
  {
    const char* p = static_cast<const char*>(b.data);
    out.insert(out.end(), p, p + b.count * b.elementSize());
  }
  putU32(out, crcOf(out.data(), out.size()));
  return out;
}

std::string decodeModel(const std::vector<char>& bytes, const std::string& where, ModelFile& result)
{
  const std::string name = "The reduction model " + where;
  if (!littleEndian())
  {
    return name + " cannot be read on a big-endian host.";
  }
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0)
  {
    return name + " is not a reduction model file (it does not start with MCVMODEL).";
  }
  if (bytes.size() < 20)
  {
    return name + " is truncated (" + std::to_string(bytes.size()) + " bytes).";
  }
  const std::uint32_t version = getU32(bytes.data() + 8);
  if (version > kModelFormatVersion || version == 0)
  {
    return name + " has format version " + std::to_string(version) + "; this build reads version " +
      std::to_string(kModelFormatVersion) + " (written by a newer Multichannel Explorer?).";
  }
  const std::uint32_t stored = getU32(bytes.data() + bytes.size() - 4);
  if (crcOf(bytes.data(), bytes.size() - 4) != stored)
  {
    return name + " is damaged or truncated: its checksum does not match its " + std::to_string(bytes.size()) +
      " bytes.";
  }
  const std::size_t headerSize = getU32(bytes.data() + 12);
  if (16 + headerSize + 4 > bytes.size())
  {
    return name + " is truncated: its header claims " + std::to_string(headerSize) + " bytes.";
  }
  Json::Value root;
  std::string why;
  if (!parseJsonObject(std::string(bytes.data() + 16, headerSize), root, why))
  {
    return name + " has a header that is not valid JSON (" + why + ").";
  }
  const Json::Value& features = root["features"];
  const Json::Value& reduction = root["reduction"];
  if (!features.isObject() || !reduction.isObject() || !root["blocks"].isArray())
  {
    return name + " lacks its features, reduction or blocks section.";
  }
  ModelFile m;
  FeatureRecipe& f = m.features;
  const std::string preset = features["featureSet"].asString();
  if (!presetNamed(preset, f.preset))
  {
    return name + " names an unknown feature set '" + preset + "'.";
  }
  const Json::Value& fit = root["fit"];
  const Json::Value* sections[] = { &features["selection"], &fit };
  visitScalarFields(m, [&](Section section, const char* key, auto& field)
    { fromJson((*sections[section])[key], field); });
  const std::string normalization = features["normalization"].asString();
  if (!normalizationNamed(normalization, f.normalization))
  {
    return name + " names an unknown normalisation '" + normalization + "'.";
  }
  std::vector<double> spacing;
  if (!readStrings(features["channels"], f.channels) || !readStrings(features["names"], f.featureNames) ||
    !readDoubles(features["offset"], f.offset) || !readDoubles(features["scale"], f.scale) ||
    !readDoubles(features["spacing"], spacing) || spacing.size() != 3)
  {
    return name + " has a malformed features section (channels, names, offset, scale or spacing).";
  }
  f.spacing = { spacing[0], spacing[1], spacing[2] };
  f.lengthUnit = features["lengthUnit"].asString();
  f.maskBackground = features["maskBackground"].asBool();
  f.backgroundThreshold = features["backgroundThreshold"].asDouble();
  if (f.channels.empty())
  {
    return name + " names no channel.";
  }

  ReductionModel& r = m.reduction;
  if (!reductionMethodFromName(reduction["method"].asString(), r.method))
  {
    return name + " names an unknown method '" + reduction["method"].asString() + "'.";
  }
  r.outputDimension = reduction["outputDimension"].asInt();
  r.featureColumns = reduction["featureColumns"].asInt();
  r.references = static_cast<std::size_t>(reduction["references"].asUInt64());
  r.referenceRadius = reduction["referenceRadius"].asDouble();
  r.varianceRetained = reduction["varianceRetained"].asDouble();
  r.trustworthiness =
    reduction["trustworthiness"].isNull() ? std::nan("") : reduction["trustworthiness"].asDouble();
  std::vector<double> used;
  if (!readDoubles(reduction["usedColumns"], used) || !readDoubles(reduction["eigenvalues"], r.eigenvalues))
  {
    return name + " has a malformed reduction section (usedColumns or eigenvalues).";
  }
  r.usedColumns.assign(used.begin(), used.end());

  for (int a = 0; a < 3 && fit["volumeDimensions"].isArray(); ++a)
  {
    m.fit.volumeDimensions[a] = fit["volumeDimensions"][a].asInt();
  }

  // The blocks, in the header's order, must fill the file up to the checksum exactly.
  std::size_t at = 16 + headerSize;
  for (const Json::Value& entry : root["blocks"])
  {
    const std::string blockName = entry["name"].asString(), type = entry["type"].asString();
    const std::size_t count = static_cast<std::size_t>(entry["count"].asUInt64());
    const std::size_t size = type == "float64" ? 8 : 4;
    if ((type != "float32" && type != "float64") || count > (bytes.size() - 4 - at) / size)
    {
      return name + " is truncated or malformed at its block '" + blockName + "'.";
    }
    const char* p = bytes.data() + at;
    if (blockName == "referenceFeatures" && type == "float32")
    {
      r.referenceFeatures.resize(count);
      std::memcpy(r.referenceFeatures.data(), p, count * size);
    }
    else if (blockName == "referenceCoordinates" && type == "float32")
    {
      r.referenceCoordinates.resize(count);
      std::memcpy(r.referenceCoordinates.data(), p, count * size);
    }
    else if (blockName == "pcaMean" && type == "float64")
    {
      r.pcaMean.resize(count);
      std::memcpy(r.pcaMean.data(), p, count * size);
    }
    else if (blockName == "pcaAxes" && type == "float64")
    {
      r.pcaAxes.resize(count);
      std::memcpy(r.pcaAxes.data(), p, count * size);
    }
    // Other blocks (a later minor addition) are skipped.
    at += count * size;
  }
  if (at != bytes.size() - 4)
  {
    return name + " has " + std::to_string(bytes.size() - 4 - at) + " bytes its header does not describe.";
  }

  const std::size_t F = static_cast<std::size_t>(r.featureColumns);
  if (f.featureNames.size() != F || f.offset.size() != F || f.scale.size() != F)
  {
    return name + " describes " + std::to_string(F) + " feature columns but names " +
      std::to_string(f.featureNames.size()) + " with " + std::to_string(f.offset.size()) + " offsets and " +
      std::to_string(f.scale.size()) + " scales.";
  }
  const int perChannel = FeatureSelection::forPreset(f.preset, f.selection).perChannel();
  if (static_cast<std::size_t>(perChannel) * f.channels.size() != F)
  {
    return name + " has " + std::to_string(F) + " feature columns, not the " + std::to_string(perChannel) +
      " per channel of its feature set for " + std::to_string(f.channels.size()) + " channel(s).";
  }
  for (std::size_t c = 0; c < F; ++c)
  {
    if (!std::isfinite(f.offset[c]) || !std::isfinite(f.scale[c]))
    {
      return name + " has a non-finite normalisation for feature '" + f.featureNames[c] + "'.";
    }
  }
  for (double s : f.spacing)
  {
    if (!std::isfinite(s) || s <= 0)
    {
      return name + " has a fit-volume spacing that is not a positive number.";
    }
  }
  const std::string broken = r.check();
  if (!broken.empty())
  {
    return name + " is not usable: " + broken + ".";
  }
  result = std::move(m);
  return {};
}

std::string readFileBytes(const std::string& path, std::vector<char>& bytes)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    return vtksys::SystemTools::FileExists(path) ? "cannot be opened (permissions?)" : "does not exist";
  }
  bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad())
  {
    return "could not be read";
  }
  return {};
}

std::string writeFileAtomically(const std::string& path, const std::vector<char>& bytes)
{
  const std::string temporary = path + ".partial";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out)
    {
      return "cannot be created (" + std::string(std::strerror(errno)) + ")";
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out)
    {
      const std::string why = std::strerror(errno);
      out.close();
      std::remove(temporary.c_str());
      return "could not be written (" + why + ")";
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0)
  {
    const std::string why = std::strerror(errno);
    std::remove(temporary.c_str());
    return "could not be put in place (" + why + ")";
  }
  return {};
}

} // namespace vtkhelpers
} // namespace mcv
