// The page directories of a TIFF file, read by walking the chain of directories (IFDs)
// ourselves, so that vtkCheckedTIFFReader can check a file before libtiff and
// vtkTIFFReader read it: libtiff stops at a directory that lies beyond the end of a cut
// file and reports the pages before it as the whole file, and reads strips that end beyond
// the file into whatever its buffer held.
#ifndef TiffDirectories_h
#define TiffDirectories_h

#include <cstdint> // for std::uint64_t
#include <string>  // for std::string
#include <vector>  // for std::vector

namespace mcv
{

struct TiffPage
{
  std::uint64_t Width = 0;
  std::uint64_t Height = 0;
  int BitsPerSample = 1;
  int SamplesPerPixel = 1;
  int SampleFormat = 1; // 1 unsigned, 2 signed, 3 float
  int Compression = 1;  // 1 none
  std::uint64_t DataBytes = 0; // the strips' (or tiles') byte counts, summed
  std::vector<std::uint64_t> DataOffsets; // where each strip (or tile) starts
  int PageCount = 0;           // the total of the PageNumber tag (0 when absent)
  std::uint64_t DirectoryOffset = 0; // where the page's directory starts in the file

  // Read on the first page only (where ImageJ and OME-TIFF keep what the file holds):
  std::string Description;     // ImageDescription (270), "" when absent
  double XResolution = 0;      // pixels per unit (282); 0 when absent
  double YResolution = 0;      // (283)
  std::vector<std::uint64_t> IJMetadataByteCounts; // ImageJ's IJMetadataByteCounts (50838)
  std::string IJMetadata;      // ImageJ's IJMetadata (50839), raw bytes
  bool BigEndian = false;      // the file's byte order (IJMetadata's text follows it)
};

// True when the file starts with a TIFF or BigTIFF header (either byte order).
bool startsLikeTiff(const std::string& name);

// Reads every page directory of the file into `pages`. "" on success; else what is wrong
// with the file: "is not a TIFF file ...", "is truncated: the directory of page 91 starts at
// byte ..., beyond its end (... bytes)", "is truncated: the image data of page 1 ends at
// byte ..., the file holds ...", a loop in the chain of directories.
std::string readTiffDirectories(const std::string& name, std::vector<TiffPage>& pages);

} // namespace mcv

#endif
