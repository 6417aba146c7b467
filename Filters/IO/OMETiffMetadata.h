// The plane map of an OME-TIFF file: the OME-XML of its first ImageDescription (written by
// Bio-Formats, Fiji's "Save As OME-TIFF", tifffile's imwrite(..., ome=True)). Read: the first
// Image (series; the map's Warning says when there are more) and its Pixels (DimensionOrder, SizeX/Y/Z/C/T, Type, PhysicalSizeX/Y/Z and their units,
// TimeIncrement and its unit), its Channel names and its TiffData elements (IFD, FirstZ,
// FirstC, FirstT, PlaneCount, and UUID FileName for a set of files in one folder).
//
// Lengths are converted to µm (OME's default unit), times to seconds. The XML is parsed
// with pugixml (Debian's libpugixml-dev; VTK's own copy is internal to VTK): a DOM with
// namespace-prefixed names, free of VTK, so the parser is tested without ParaView.
#ifndef OMETiffMetadata_h
#define OMETiffMetadata_h

#include "TiffPlaneMap.h"

#include <string> // for std::string

namespace mcv
{

// True when the description looks like OME-XML (an <OME> root element).
bool isOMEDescription(const std::string& description);

// Fills the map from the OME-XML; `fileName` is the name of the file that holds it (the
// file of TiffData without a UUID FileName, Files[0]). "" on success; else the problem,
// e.g. "has OME-XML that cannot be parsed (...)", "has PhysicalSizeZUnit="furlong" in its
// OME-XML, a length unit this reader does not know (...)", "has SizeC=3 in its OME-XML but 2
// Channel elements", "has a TiffData (number 2) whose planes go past the SizeZ x SizeC x
// SizeT = 12 planes of its Pixels".
std::string parseOME(const std::string& xml, const std::string& fileName, TiffPlaneMap& map);

} // namespace mcv

#endif
