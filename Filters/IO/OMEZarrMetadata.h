// The image metadata of an OME-Zarr (OME-NGFF 0.4) image: the `.zattrs` of its group, whose
// `multiscales[0]` lists the axes and the resolution levels (array paths with their scale
// and translation) and whose `omero` block names and colours the channels. VTK-free apart
// from the JSON parser (VTK's jsoncpp).
#ifndef OMEZarrMetadata_h
#define OMEZarrMetadata_h

#include <string> // for std::string
#include <vector> // for std::vector

namespace mcv
{
namespace zarr
{

struct Axis
{
  std::string Name; // one of t, c, z, y, x
  std::string Unit; // "" when none is given
};

struct Level
{
  std::string Path; // the array's folder, relative to the image's
  // Per axis (in the order of the axes): world size of one element and world position of
  // element 0, the dataset's transformations followed by those of the whole multiscale.
  std::vector<double> Scale;
  std::vector<double> Translation;
};

struct Channel
{
  std::string Label; // "" when the file gives none
  std::string Color; // hex RGB as written (e.g. "FF0000"), "" when none
};

struct ImageMeta
{
  std::vector<Axis> Axes;
  std::vector<Level> Levels; // finest first, as the spec orders them
  std::vector<Channel> Channels; // from omero; may be empty

  // Index of the axis called `name`, -1 when the image has none.
  int AxisIndex(const std::string& name) const;
};

// Parses the text of a `.zattrs` file. Axes must be a subset of t, c, z, y, x in that order
// with y and x present (NGFF 0.4); version 0.4 `axes` objects and 0.3 name lists are read.
// Returns "" on success, else the problem.
std::string parseImageMeta(const std::string& text, ImageMeta& meta);

} // namespace zarr
} // namespace mcv

#endif
