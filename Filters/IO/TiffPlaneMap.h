// Where the 2D planes of a multichannel, multi-frame TIFF volume lie: which file and page
// holds channel c of slice z of frame t, with the voxel spacing and its unit, the time of
// each frame and the channel names. Built from an ImageJ hyperstack's description
// (ImageJHyperstack.h) or from OME-XML (OMETiffMetadata.h); vtkCheckedTIFFReader reads the
// planes it names. Free of VTK, so that the parsers are tested on their own.
#ifndef TiffPlaneMap_h
#define TiffPlaneMap_h

#include <cstdint> // for std::uint64_t
#include <string>  // for std::string
#include <vector>  // for std::vector

namespace mcv
{

struct TiffPlaneRef
{
  int File = -1;          // index into TiffPlaneMap::Files; -1: no page holds this plane
  std::uint64_t Page = 0; // 0-based page (IFD) of that file
};

struct TiffPlaneMap
{
  std::string Format; // "ImageJ hyperstack" or "OME-TIFF": named in messages
  std::uint64_t SizeX = 0;
  std::uint64_t SizeY = 0;
  int SizeZ = 1;
  int SizeC = 1;
  int SizeT = 1;
  // The files that hold planes, as the metadata names them (OME: relative to the folder of
  // the file opened); Files[0] is the file opened.
  std::vector<std::string> Files;
  std::vector<TiffPlaneRef> Planes; // index (t * SizeZ + z) * SizeC + c
  double Spacing[3] = { 1, 1, 1 };
  std::string LengthUnit;              // of Spacing, e.g. "µm"; "pixel" when the file has none
  std::vector<double> TimeValues;      // one per frame
  std::string TimeUnit;                // of TimeValues, e.g. "s"; "frame" for 0, 1, 2...
  std::vector<std::string> ChannelNames; // one per channel, unique, not empty
  // The sample type the metadata declares (8, 16 or 32 bits; 1 unsigned, 2 signed, 3
  // float); 0 when it declares none (ImageJ: the pages tell).
  int BitsPerSample = 0;
  int SampleFormat = 0;
  // What the reader should warn about while reading the file (e.g. the other series of a
  // multi-series OME-TIFF, which are not read); "" when nothing.
  std::string Warning;

  // Sizes Planes (every plane missing), TimeValues (0, 1, 2...) and ChannelNames (C1...)
  // for SizeC, SizeZ and SizeT; false when they are not all positive or their product is
  // beyond 2^31 planes.
  bool Allocate();
  TiffPlaneRef& At(int c, int z, int t);
  const TiffPlaneRef& At(int c, int z, int t) const;
};

// "" when every plane of the map has a page, and each page lies within its file, whose
// page count is pageCounts[file]; else, e.g., "has no page for channel 2, slice 5, frame 1"
// or "has its plane for channel 1, slice 3, frame 1 on page 200 of 'b.ome.tif', which holds
// 120 pages".
std::string checkPlaneMap(const TiffPlaneMap& map, const std::vector<std::uint64_t>& pageCounts);

// Replaces names that are empty or repeated by C<n> (n the channel's 1-based number), and
// a repeat of those by C<n>_<k>, so that every channel gets a distinct point array.
void makeChannelNamesUnique(std::vector<std::string>& names);

} // namespace mcv

#endif
