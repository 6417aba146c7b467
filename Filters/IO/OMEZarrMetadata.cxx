#include "OMEZarrMetadata.h"

#include "vtk_jsoncpp.h"

#include "../Common/mcvJsonObject.h"

#include <cmath>
#include <sstream>

namespace mcv
{
namespace zarr
{
namespace
{
const char* const AxisOrder = "tczyx";

// The scale and translation of a list of coordinateTransformations of `n` axes, applied
// after (scale, translation); "" or the problem, `where` naming the list.
std::string applyTransformations(const Json::Value& list, std::size_t n,
  std::vector<double>& scale, std::vector<double>& translation, const std::string& where)
{
  if (list.isNull())
  {
    return "";
  }
  if (!list.isArray())
  {
    return "has " + where + " coordinateTransformations that are not a list";
  }
  for (const Json::Value& t : list)
  {
    const std::string type = t["type"].isString() ? t["type"].asString() : "";
    if (type == "identity")
    {
      continue;
    }
    if (type != "scale" && type != "translation")
    {
      return "has a " + where + " coordinateTransformation of type '" + type +
        "' (scale, translation and identity can be read)";
    }
    const Json::Value& values = t[type];
    if (!values.isArray())
    {
      return "has a " + where + " " + type + " given by '" +
        (t["path"].isString() ? t["path"].asString() : std::string("?")) +
        "' instead of values in the metadata, which cannot be read";
    }
    if (values.size() != n)
    {
      return "has a " + where + " " + type + " of " + std::to_string(values.size()) +
        " values for " + std::to_string(n) + " axes";
    }
    for (Json::ArrayIndex i = 0; i < n; ++i)
    {
      if (!values[i].isNumeric() || !std::isfinite(values[i].asDouble()))
      {
        return "has a " + where + " " + type + " with a value that is not a finite number";
      }
      const double v = values[i].asDouble();
      if (type == "scale")
      {
        if (v == 0)
        {
          return "has a " + where + " scale of 0 along axis " + std::to_string(i);
        }
        scale[i] *= v;
        translation[i] *= v;
      }
      else
      {
        translation[i] += v;
      }
    }
  }
  return "";
}
} // namespace

//------------------------------------------------------------------------------
int ImageMeta::AxisIndex(const std::string& name) const
{
  for (std::size_t i = 0; i < this->Axes.size(); ++i)
  {
    if (this->Axes[i].Name == name)
    {
      return static_cast<int>(i);
    }
  }
  return -1;
}

//------------------------------------------------------------------------------
std::string parseImageMeta(const std::string& text, ImageMeta& meta)
{
  meta = ImageMeta();
  Json::Value root;
  std::string why;
  if (!mcv::vtkhelpers::parseJsonObject(text, root, why))
  {
    return "has a .zattrs that is not valid JSON (" + why + ")";
  }
  const Json::Value& multiscales = root["multiscales"];
  if (!multiscales.isArray() || multiscales.empty() || !multiscales[0].isObject())
  {
    return "has no multiscales in its .zattrs (not an OME-Zarr image)";
  }
  const Json::Value& ms = multiscales[0];

  // Axes: NGFF 0.4 objects {"name", "type", "unit"}, or 0.3 plain names.
  const Json::Value& axes = ms["axes"];
  if (axes.isNull())
  {
    // NGFF 0.1/0.2: always 5D t, c, z, y, x.
    for (const char* a = AxisOrder; *a; ++a)
    {
      meta.Axes.push_back({ std::string(1, *a), "" });
    }
  }
  else if (!axes.isArray() || axes.empty())
  {
    return "has multiscales axes that are not a list";
  }
  for (const Json::Value& a : axes)
  {
    Axis axis;
    if (a.isString())
    {
      axis.Name = a.asString();
    }
    else if (a.isObject() && a["name"].isString())
    {
      axis.Name = a["name"].asString();
      axis.Unit = a["unit"].isString() ? a["unit"].asString() : "";
    }
    else
    {
      return "has a multiscales axis without a name";
    }
    meta.Axes.push_back(axis);
  }
  std::string names;
  for (const Axis& a : meta.Axes)
  {
    names += a.Name;
  }
  // A subsequence of "tczyx" that ends with y and x.
  std::size_t at = 0;
  bool ordered = names.size() >= 2 && names.compare(names.size() - 2, 2, "yx") == 0;
  for (const Axis& a : meta.Axes)
  {
    const std::size_t found = a.Name.size() == 1 ? std::string(AxisOrder).find(a.Name, at)
                                                 : std::string::npos;
    ordered = ordered && found != std::string::npos;
    at = found == std::string::npos ? at : found + 1;
  }
  if (!ordered)
  {
    std::string list;
    for (const Axis& a : meta.Axes)
    {
      list += (list.empty() ? "" : ", ") + a.Name;
    }
    return "has axes (" + list +
      ") that are not a subset of t, c, z, y, x in that order ending with y, x";
  }

  const std::size_t n = meta.Axes.size();
  const Json::Value& datasets = ms["datasets"];
  if (!datasets.isArray() || datasets.empty())
  {
    return "has no multiscales datasets (resolution levels)";
  }
  for (Json::ArrayIndex i = 0; i < datasets.size(); ++i)
  {
    const Json::Value& d = datasets[i];
    if (!d["path"].isString() || d["path"].asString().empty())
    {
      return "has multiscales dataset " + std::to_string(i) + " without a path";
    }
    Level level;
    level.Path = d["path"].asString();
    level.Scale.assign(n, 1.0);
    level.Translation.assign(n, 0.0);
    std::string problem = applyTransformations(d["coordinateTransformations"], n, level.Scale,
      level.Translation, "dataset '" + level.Path + "'");
    if (problem.empty())
    {
      problem = applyTransformations(
        ms["coordinateTransformations"], n, level.Scale, level.Translation, "multiscale");
    }
    if (!problem.empty())
    {
      return problem;
    }
    meta.Levels.push_back(level);
  }

  const Json::Value& channels = root["omero"]["channels"];
  if (channels.isArray())
  {
    for (const Json::Value& c : channels)
    {
      Channel channel;
      channel.Label = c["label"].isString() ? c["label"].asString() : "";
      channel.Color = c["color"].isString() ? c["color"].asString() : "";
      meta.Channels.push_back(channel);
    }
  }
  return "";
}

} // namespace zarr
} // namespace mcv
