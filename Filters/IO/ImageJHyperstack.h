// The plane map of an ImageJ hyperstack: a multi-page TIFF whose first ImageDescription
// reads "ImageJ=...\nimages=N\nchannels=C\nslices=Z\nframes=T\nhyperstack=true\n
// spacing=S\nunit=U\nfinterval=F...", written by ImageJ/Fiji and by tifffile
// (imwrite(..., imagej=True)). Its pages hold the planes in the order TZCYX (channel
// fastest, then slice, then frame); any of C, Z, T may be absent (1). X and Y spacing come
// from XResolution/YResolution (pixels per unit), Z from spacing=, all in unit=; frames are
// finterval= apart (in tunit=, seconds by default). Channel names come from the slice
// labels of the IJMetadata tag when the first frame's first slice labels its channels.
#ifndef ImageJHyperstack_h
#define ImageJHyperstack_h

#include "TiffPlaneMap.h"

#include <cstdint> // for std::uint64_t
#include <string>  // for std::string
#include <vector>  // for std::vector

namespace mcv
{

// What an ImageJ file's first page holds (TiffDirectories.h reads it).
struct ImageJTags
{
  std::string Description;
  double XResolution = 0; // pixels per unit; 0 when absent
  double YResolution = 0;
  std::vector<std::uint64_t> MetadataByteCounts; // IJMetadataByteCounts (50838)
  std::string Metadata;                          // IJMetadata (50839)
  bool BigEndian = false;                        // the file's byte order
};

// True when the description is ImageJ's ("ImageJ=" on its first line).
bool isImageJDescription(const std::string& description);

// Fills the map's sizes, planes (all in Files[0]), spacing, units, times and names (SizeX
// and SizeY are the reader's, from the pages) from an ImageJ file of `pages` pages. "" on
// success; else the problem, e.g. "has images=12 in its ImageJ description, but channels=2
// x slices=3 x frames=3 = 18", "is missing pages: its ImageJ description counts images=18,
// the file holds 12 pages", "has unit=furlong in its ImageJ description, a length unit this
// reader does not know (...)".
std::string parseImageJ(const ImageJTags& tags, std::uint64_t pages, TiffPlaneMap& map);

// The slice labels of IJMetadata ("labl" entries, UTF-16 text, decoded to UTF-8); empty
// when there are none or the tag is malformed (the labels are then left out, not an error).
std::vector<std::string> imageJLabels(const ImageJTags& tags);

} // namespace mcv

#endif
