// Channel names from file names, shared by the checked readers (MCV::IOVolPack), which name
// the array they read after its file, and vtkMergeChannels, which names a channel that
// still has a reader's generic array name (ParaView's own readers) after its file.
// Header-only, standard library only.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstring>
#include <string>

namespace mcv
{

// The file name without its folder and without the volume extensions a reader of the
// suite or of ParaView reads ("/data/ch2.nii.gz" -> "ch2", "cells.ome.tif" -> "cells",
// "brain.mhd" -> "brain"); the name without its folder when no such extension ends it.
inline std::string fileStem(const std::string& path)
{
  const std::size_t slash = path.find_last_of("/\\");
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  // Longest first: ".ome.tif" before ".tif", ".nii.gz" before ".gz".
  static const char* const extensions[] = { ".ome.tiff", ".ome.tif", ".ome.zarr", ".nii.gz",
    ".img.gz", ".hdr.gz", ".tiff", ".zarr", ".nii", ".hdr", ".img", ".mhd", ".mha", ".tif",
    ".den", ".vti", ".vtk", ".nrrd", ".nhdr", ".raw", ".gz" };
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* extension : extensions)
  {
    const std::size_t n = std::strlen(extension);
    if (lower.size() > n && lower.compare(lower.size() - n, n, extension) == 0)
    {
      return name.substr(0, name.size() - n);
    }
  }
  return name;
}

// The name of a file series after its first file: the stem without the number that counts
// the files and the separator before it ("vol_000.nii.gz" -> "vol", "t1-07.mha" -> "t1"),
// the stem itself when nothing else would be left ("0001.nii" -> "0001").
inline std::string seriesStem(const std::string& firstFile)
{
  const std::string stem = fileStem(firstFile);
  std::size_t end = stem.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(stem[end - 1])))
  {
    --end;
  }
  while (end > 0 && std::strchr("_-. ", stem[end - 1]))
  {
    --end;
  }
  return end == 0 ? stem : stem.substr(0, end);
}

// Array names VTK's and ParaView's image readers give whatever file they read: such a name
// says nothing about the channel, so the channel is named after its file instead.
inline bool isGenericReaderArrayName(const char* name)
{
  if (!name || !*name)
  {
    return true;
  }
  static const char* const generic[] = { "NIFTI", "MetaImage", "Tiff Scalars", "ImageFile",
    "PNGImage", "JPEGImage", "DICOMImage" };
  for (const char* g : generic)
  {
    if (std::strcmp(name, g) == 0)
    {
      return true;
    }
  }
  return false;
}

} // namespace mcv
