#include "vtkCheckedTIFFReader.h"

#include "CheckedReading.h"
#include "ImageJHyperstack.h"
#include "OMETiffMetadata.h"
#include "TiffDirectories.h"
#include "TiffPlaneMap.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtk_tiff.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <sstream>

vtkStandardNewMacro(vtkCheckedTIFFReader);

namespace
{
// libtiff's errors while this reader reads (vtkTIFFReader silences them, and goes on with
// whatever a strip that failed to decode left in its buffer). libtiff's handler is global:
// it is ours only for the time of one read.
class LibtiffErrors
{
public:
  LibtiffErrors()
    : Previous(TIFFSetErrorHandler(&LibtiffErrors::OnError))
  {
    First() = "";
  }
  ~LibtiffErrors() { TIFFSetErrorHandler(this->Previous); }
  LibtiffErrors(const LibtiffErrors&) = delete;
  void operator=(const LibtiffErrors&) = delete;

  static std::string& First()
  {
    static std::string first;
    return first;
  }

private:
  static void OnError(const char* module, const char* format, va_list args)
  {
    if (First().empty())
    {
      char text[512];
      std::vsnprintf(text, sizeof(text), format, args);
      First() = std::string("libtiff: ") + (module ? std::string(module) + ": " : "") + text;
    }
  }

  TIFFErrorHandler Previous;
};

// The VTK type of samples of `bits` bits in TIFF's SampleFormat (1 unsigned, 2 signed, 3
// float); -1 when none.
int vtkTypeOf(int bits, int format)
{
  switch (bits * 10 + format)
  {
    case 81: return VTK_UNSIGNED_CHAR;
    case 82: return VTK_SIGNED_CHAR;
    case 161: return VTK_UNSIGNED_SHORT;
    case 162: return VTK_SHORT;
    case 321: return VTK_UNSIGNED_INT;
    case 322: return VTK_INT;
    case 323: return VTK_FLOAT;
    default: return -1;
  }
}

std::string typeName(int bits, int format)
{
  return std::string(format == 3 ? "float" : format == 2 ? "int" : "uint") + std::to_string(bits);
}

// Decodes rows y0..y1 of the current page of `tiff` into `page` (a whole page: height rows
// of width samples of `sample` bytes; other rows are left as they are) through libtiff, any
// compression it decodes. Only the strips, or the tiles, that hold those rows are decoded,
// so that a process of a parallel run decodes about its share. "" on success, else the
// problem.
std::string readPage(TIFF* tiff, std::size_t width, std::size_t height, std::size_t sample,
  std::size_t y0, std::size_t y1, unsigned char* page)
{
  const std::size_t row = width * sample;
  if (TIFFIsTiled(tiff))
  {
    std::uint32_t tw = 0, th = 0;
    TIFFGetField(tiff, TIFFTAG_TILEWIDTH, &tw);
    TIFFGetField(tiff, TIFFTAG_TILELENGTH, &th);
    if (tw == 0 || th == 0)
    {
      return "has tiles of 0 pixels";
    }
    std::vector<unsigned char> tile(static_cast<std::size_t>(tw) * th * sample);
    for (std::size_t ty = y0 - y0 % th; ty <= y1; ty += th)
    {
      for (std::size_t tx = 0; tx < width; tx += tw)
      {
        const ttile_t index = TIFFComputeTile(
          tiff, static_cast<std::uint32_t>(tx), static_cast<std::uint32_t>(ty), 0, 0);
        if (TIFFReadEncodedTile(tiff, index, tile.data(), static_cast<tmsize_t>(tile.size())) < 0)
        {
          return "has a tile that libtiff cannot decode (tile " + std::to_string(index + 1) + ")";
        }
        const std::size_t w = std::min<std::size_t>(tw, width - tx);
        for (std::size_t y = std::max(ty, y0); y < std::min<std::size_t>(ty + th, y1 + 1); ++y)
        {
          std::memcpy(
            page + y * row + tx * sample, tile.data() + (y - ty) * tw * sample, w * sample);
        }
      }
    }
    return "";
  }
  std::uint32_t rowsPerStrip = 0;
  if (!TIFFGetFieldDefaulted(tiff, TIFFTAG_ROWSPERSTRIP, &rowsPerStrip) || rowsPerStrip == 0 ||
    rowsPerStrip > height)
  {
    rowsPerStrip = static_cast<std::uint32_t>(height);
  }
  const tstrip_t strips = TIFFNumberOfStrips(tiff);
  for (tstrip_t s = static_cast<tstrip_t>(y0 / rowsPerStrip);
       s < strips && static_cast<std::size_t>(s) * rowsPerStrip <= y1; ++s)
  {
    const std::size_t first = static_cast<std::size_t>(s) * rowsPerStrip;
    const std::size_t rows = std::min<std::size_t>(rowsPerStrip, height - first);
    const tmsize_t wanted = static_cast<tmsize_t>(rows * row);
    const tmsize_t got = TIFFReadEncodedStrip(tiff, s, page + first * row, wanted);
    if (got < wanted)
    {
      return "has a strip that libtiff cannot decode whole (strip " + std::to_string(s + 1) +
        ": " + std::to_string(got < 0 ? 0 : got) + " of " + std::to_string(wanted) + " bytes)";
    }
  }
  if (static_cast<std::size_t>(strips) * rowsPerStrip < y1 + 1)
  {
    return "has " + std::to_string(strips) + " strips of " + std::to_string(rowsPerStrip) +
      " rows, fewer than its " + std::to_string(height) + " rows";
  }
  return "";
}

std::vector<std::uint64_t> directoryOffsets(const std::vector<mcv::TiffPage>& pages)
{
  std::vector<std::uint64_t> offsets;
  for (const mcv::TiffPage& page : pages)
  {
    offsets.push_back(page.DirectoryOffset);
  }
  return offsets;
}

std::string pixels(const mcv::TiffPage& p)
{
  std::ostringstream text;
  text << p.Width << " x " << p.Height << " pixels of " << p.BitsPerSample << " bits";
  if (p.SamplesPerPixel != 1)
  {
    text << " x " << p.SamplesPerPixel << " samples";
  }
  return text.str();
}

bool sameKind(const mcv::TiffPage& a, const mcv::TiffPage& b)
{
  return a.Width == b.Width && a.Height == b.Height && a.BitsPerSample == b.BitsPerSample &&
    a.SamplesPerPixel == b.SamplesPerPixel && a.SampleFormat == b.SampleFormat;
}

// "" when the pages of one file can be the slices of a volume; else what is wrong.
std::string checkPages(const std::string& name, const std::vector<mcv::TiffPage>& pages)
{
  const mcv::TiffPage& first = pages[0];
  std::ostringstream msg;
  if (first.Width < 1 || first.Height < 1)
  {
    msg << "has a page of " << first.Width << " x " << first.Height
        << " pixels (at least 1 x 1 expected)";
    return msg.str();
  }
  if ((first.BitsPerSample != 8 && first.BitsPerSample != 16 && first.BitsPerSample != 32) ||
    first.SampleFormat < 1 || first.SampleFormat > 3 || first.SamplesPerPixel < 1)
  {
    msg << "has pages of " << first.BitsPerSample << " bits per sample (sample format "
        << first.SampleFormat << "), which cannot be read (8, 16 or 32 bit integers or 32 bit "
        << "floats can)";
    return msg.str();
  }
  // A file cut at a page boundary still has whole directories: its page numbers tell.
  if (first.PageCount > static_cast<int>(pages.size()))
  {
    msg << "is truncated: its pages are numbered as " << first.PageCount << ", the file holds "
        << pages.size();
    return msg.str();
  }
  const double bytes =
    static_cast<double>(first.Width) * first.Height * first.SamplesPerPixel * first.BitsPerSample / 8;
  for (std::size_t i = 0; i < pages.size(); ++i)
  {
    if (!sameKind(pages[i], first))
    {
      msg << "has page " << i + 1 << " of " << pixels(pages[i]) << " after page 1 of "
          << pixels(first) << " (the pages of a volume must match)";
      return msg.str();
    }
    // Deflate strips are decompressed whole: libtiff stops once it has a strip's pixels and
    // never sees the checksum at the end of a corrupt stream.
    double held = static_cast<double>(pages[i].DataBytes);
    const bool deflate = pages[i].Compression == 8 || pages[i].Compression == 32946;
    if (deflate)
    {
      held = 0;
      for (std::uint64_t offset : pages[i].DataOffsets)
      {
        std::string error;
        const std::int64_t n = mcv::inflatedBytes(
          name, static_cast<std::int64_t>(offset), mcv::Compression::ZlibOrGzip, error);
        if (n < 0)
        {
          msg << "has a Deflate strip on page " << i + 1 << " at byte " << offset << " that "
              << error;
          return msg.str();
        }
        held += static_cast<double>(n);
      }
    }
    if ((pages[i].Compression == 1 || deflate) && held < bytes) // other codecs: unknown
    {
      msg << "is truncated: page " << i + 1 << " holds " << held << " bytes of pixels, its "
          << pixels(first) << " need " << bytes;
      return msg.str();
    }
  }
  return "";
}
} // namespace

//------------------------------------------------------------------------------
// The plane map of the file being read, when it is an ImageJ hyperstack or an OME-TIFF.
class vtkCheckedTIFFReader::vtkInternals
{
public:
  bool HasMap = false;
  mcv::TiffPlaneMap Map;
  std::vector<std::string> Paths; // the map's Files, as paths
  // Where each page's directory starts, per file: libtiff goes to a page by its offset
  // at once (TIFFSetDirectory would walk the chain from the first page every time).
  std::vector<std::vector<std::uint64_t>> Directories;
  int Bits = 0;
  int Format = 0;
  std::string Contents; // what the file holds besides its grid (vtkCheckedTIFFReader::Contents)

  // Builds the map of the file `name` (whose directories are `pages`) when its first page's
  // description is ImageJ's or OME-XML, and checks the files and pages it names. "" when
  // done, or when the file is neither (HasMap false); else the problem.
  std::string Build(const std::string& name, const std::vector<mcv::TiffPage>& pages)
  {
    this->HasMap = false;
    this->Map = mcv::TiffPlaneMap();
    const mcv::TiffPage& first = pages[0];
    const std::string base = vtksys::SystemTools::GetFilenameName(name);
    std::string problem;
    if (mcv::isOMEDescription(first.Description))
    {
      problem = mcv::parseOME(first.Description, base, this->Map);
    }
    else if (mcv::isImageJDescription(first.Description))
    {
      mcv::ImageJTags tags;
      tags.Description = first.Description;
      tags.XResolution = first.XResolution;
      tags.YResolution = first.YResolution;
      tags.MetadataByteCounts = first.IJMetadataByteCounts;
      tags.Metadata = first.IJMetadata;
      tags.BigEndian = first.BigEndian;
      problem = mcv::parseImageJ(tags, pages.size(), this->Map);
      this->Map.Files.assign(1, base);
      this->Map.SizeX = first.Width;
      this->Map.SizeY = first.Height;
      // RGB pages (ImageJ's RGB stacks) stay as vtkTIFFReader reads them, unless they
      // claim channels or frames that would then be folded into the slices.
      if (problem.empty() && first.SamplesPerPixel != 1 && this->Map.SizeC == 1 &&
        this->Map.SizeT == 1)
      {
        return "";
      }
    }
    else
    {
      return "";
    }
    if (!problem.empty())
    {
      return problem;
    }
    std::ostringstream msg;
    if (first.SamplesPerPixel != 1)
    {
      msg << "has pages of " << first.SamplesPerPixel << " samples per pixel (RGB) in an "
          << this->Map.Format << ", which this reader does not read (one sample expected)";
      return msg.str();
    }
    if (this->Map.SizeX != first.Width || this->Map.SizeY != first.Height)
    {
      msg << "has SizeX x SizeY = " << this->Map.SizeX << " x " << this->Map.SizeY
          << " in its OME-XML, but pages of " << pixels(first);
      return msg.str();
    }
    if (this->Map.BitsPerSample &&
      (this->Map.BitsPerSample != first.BitsPerSample ||
        this->Map.SampleFormat != std::max(first.SampleFormat, 1)))
    {
      msg << "declares samples of type "
          << typeName(this->Map.BitsPerSample, this->Map.SampleFormat)
          << " in its OME-XML, but its pages hold "
          << typeName(first.BitsPerSample, first.SampleFormat);
      return msg.str();
    }
    // The other files of an OME-TIFF set, in the folder of this one.
    const std::string folder = vtksys::SystemTools::GetFilenamePath(name);
    this->Paths.assign(1, name);
    this->Directories.assign(1, directoryOffsets(pages));
    std::vector<std::uint64_t> pageCounts(1, pages.size());
    for (std::size_t f = 1; f < this->Map.Files.size(); ++f)
    {
      const std::string& file = this->Map.Files[f];
      const std::string path = folder.empty() ? file : folder + "/" + file;
      std::vector<mcv::TiffPage> other;
      problem = mcv::readTiffDirectories(path, other);
      problem = problem.empty() ? checkPages(path, other) : problem;
      if (problem.empty() && !sameKind(other[0], first))
      {
        problem = "is " + pixels(other[0]) + " where the first file is " + pixels(first);
      }
      if (!problem.empty())
      {
        return "names in its OME-XML a file '" + path + "' that " + problem;
      }
      this->Paths.push_back(path);
      this->Directories.push_back(directoryOffsets(other));
      pageCounts.push_back(other.size());
    }
    problem = mcv::checkPlaneMap(this->Map, pageCounts);
    if (!problem.empty())
    {
      return problem;
    }
    this->Bits = first.BitsPerSample;
    this->Format = std::max(first.SampleFormat, 1);
    this->HasMap = true;
    std::string names;
    for (const std::string& channel : this->Map.ChannelNames)
    {
      names += (names.empty() ? "" : ", ") + channel;
    }
    this->Contents = "channels " + names + " of " + typeName(this->Bits, this->Format);
    return "";
  }
};

//------------------------------------------------------------------------------
vtkCheckedTIFFReader::vtkCheckedTIFFReader()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkCheckedTIFFReader::~vtkCheckedTIFFReader()
{
  delete this->Internals;
}

//------------------------------------------------------------------------------
void vtkCheckedTIFFReader::AddFileName(const char* name)
{
  this->Stack.emplace_back(name ? name : "");
  if (this->Stack.size() == 1)
  {
    this->SetFileName(this->Stack[0].c_str());
    return;
  }
  vtkNew<vtkStringArray> names; // a new array: vtkImageReader2 sees the change
  for (const std::string& file : this->Stack)
  {
    names->InsertNextValue(file);
  }
  this->SetFileNames(names);
}

//------------------------------------------------------------------------------
void vtkCheckedTIFFReader::RemoveAllFileNames()
{
  this->Stack.clear();
  this->SetFileName(nullptr);
  this->SetFileNames(nullptr);
}

//------------------------------------------------------------------------------
int vtkCheckedTIFFReader::CanReadFile(const char* name)
{
  if (this->Superclass::CanReadFile(name))
  {
    return 1;
  }
  // A TIFF that libtiff cannot open because it is cut or broken is taken too, so that the
  // error says why (ParaView would only say "no reader found"); other TIFFs that libtiff
  // cannot read are left to the next reader (GDAL).
  std::vector<mcv::TiffPage> pages;
  return mcv::startsLikeTiff(name) && !mcv::readTiffDirectories(name, pages).empty() ? 1 : 0;
}

//------------------------------------------------------------------------------
std::vector<std::string> vtkCheckedTIFFReader::Files()
{
  std::vector<std::string> files;
  if (vtkStringArray* names = this->GetFileNames())
  {
    for (vtkIdType i = 0; i < names->GetNumberOfValues(); ++i)
    {
      files.push_back(names->GetValue(i));
    }
  }
  else if (this->GetFileName())
  {
    files.emplace_back(this->GetFileName());
  }
  if (this->OneImageSet)
  {
    files.resize(1);
  }
  return files;
}

//------------------------------------------------------------------------------
std::string vtkCheckedTIFFReader::CheckFiles()
{
  const std::vector<std::string> files = this->Files();
  if (files.empty())
  {
    return "cannot be read (no file name was given)";
  }
  mcv::TiffPage first;
  double slices = 0;
  for (std::size_t i = 0; i < files.size(); ++i)
  {
    // In a stack, the problem is that of one of its files.
    std::ostringstream which;
    if (files.size() > 1)
    {
      which << "has a file '" << files[i] << "' (number " << i + 1 << ") that ";
    }
    std::vector<mcv::TiffPage> pages;
    std::string problem = mcv::readTiffDirectories(files[i], pages);
    if (problem.empty())
    {
      problem = checkPages(files[i], pages);
    }
    if (problem.empty() && i > 0 && !sameKind(pages[0], first))
    {
      problem = "is " + pixels(pages[0]) + " where the first file is " + pixels(first) +
        " (the slices of a stack must match)";
    }
    if (problem.empty() && files.size() > 1 && pages.size() > 1)
    {
      // Only the first page would be read: a volume taken for a slice.
      problem = "holds " + std::to_string(pages.size()) +
        " pages, where a stack of 2D slices takes one page per file (a list of files whose "
        "first file holds several pages is read as a time series of volumes instead)";
    }
    if (problem.empty() && files.size() == 1)
    {
      problem = this->Internals->Build(files[0], pages);
    }
    if (!problem.empty())
    {
      return which.str() + problem;
    }
    if (this->Internals->HasMap) // one frame of all channels is held at a time
    {
      const mcv::TiffPlaneMap& map = this->Internals->Map;
      return mcv::checkFitsInMemory(
        static_cast<double>(map.SizeX) * map.SizeY * map.SizeZ * map.SizeC,
        this->Internals->Bits / 8.0);
    }
    first = i == 0 ? pages[0] : first;
    this->Internals->Contents = pixels(first);
    slices += files.size() > 1 ? 1.0 : static_cast<double>(pages.size());
  }
  return mcv::checkFitsInMemory(static_cast<double>(first.Width) * first.Height * slices,
    first.SamplesPerPixel * first.BitsPerSample / 8.0);
}

//------------------------------------------------------------------------------
int vtkCheckedTIFFReader::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // No time steps or pieces left from an earlier file that had them.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  outInfo->Remove(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT());
  this->Internals->HasMap = false;
  this->ClassifyList();
  // The files first: libtiff would stop quietly at a cut directory.
  this->Refused = !mcv::checkedRequestInformation(this, outputVector, this->Describe(), [&] {
    if (this->Series)
    {
      return this->SeriesInformation(outInfo);
    }
    const std::string problem = this->CheckFiles();
    if (!problem.empty())
    {
      return problem;
    }
    if (this->Internals->HasMap)
    {
      if (!this->Internals->Map.Warning.empty())
      {
        vtkWarningMacro(<< this->Describe() << " " << this->Internals->Map.Warning << ".");
      }
      return this->PlaneMapInformation(outInfo);
    }
    if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
    {
      return std::string("cannot be read");
    }
    // The file's resolution is used only when it is positive; CustomDataSpacing as it is set.
    return mcv::checkSpacing(this->GetDataSpacing(), 3,
      this->GetSpacingSpecifiedFlag() ? "CustomDataSpacing" : "the spacing of the file");
  });
  return this->Refused ? 0 : 1;
}

//------------------------------------------------------------------------------
int vtkCheckedTIFFReader::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return mcv::checkedRequestData(this, outputVector, this->Describe(), this->Refused, [&] {
    LibtiffErrors errors;
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    const int ok = this->Series ? this->ReadSeriesStep(outInfo)
      : this->Internals->HasMap ? this->ReadPlanes(outInfo)
                                : this->Superclass::RequestData(request, inputVector, outputVector);
    if (!LibtiffErrors::First().empty())
    {
      vtkErrorMacro(<< LibtiffErrors::First()); // caught by checkedRequestData
    }
    return ok;
  });
}

//------------------------------------------------------------------------------
std::string vtkCheckedTIFFReader::Describe()
{
  const std::vector<std::string> files = this->Files();
  if (files.size() > 1)
  {
    return "TIFF " + std::string(this->Series ? "time series" : "stack") + " of " +
      std::to_string(files.size()) + " files";
  }
  return "TIFF file '" + (files.empty() ? std::string() : files[0]) + "'";
}

//------------------------------------------------------------------------------
std::string vtkCheckedTIFFReader::PlaneMapInformation(vtkInformation* outInfo)
{
  const mcv::TiffPlaneMap& map = this->Internals->Map;
  double spacing[3] = { map.Spacing[0], map.Spacing[1], map.Spacing[2] };
  if (this->GetSpacingSpecifiedFlag())
  {
    std::copy(this->GetDataSpacing(), this->GetDataSpacing() + 3, spacing);
  }
  const std::string problem = mcv::checkSpacing(spacing, 3,
    this->GetSpacingSpecifiedFlag() ? "CustomDataSpacing" : "the spacing of the file");
  if (!problem.empty())
  {
    return problem;
  }
  if (map.SizeX > 2147483647u || map.SizeY > 2147483647u)
  {
    return "has planes of " + std::to_string(map.SizeX) + " x " + std::to_string(map.SizeY) +
      " pixels, beyond the extent of VTK's image data";
  }
  const int extent[6] = { 0, static_cast<int>(map.SizeX) - 1, 0, static_cast<int>(map.SizeY) - 1,
    0, map.SizeZ - 1 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), this->GetDataOrigin(), 3);
  vtkDataObject::SetPointDataActiveScalarInfo(
    outInfo, vtkTypeOf(this->Internals->Bits, this->Internals->Format), 1);
  // Any extent is read from its own slices: each process of a parallel run reads its slab.
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  if (map.SizeT > 1)
  {
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), map.TimeValues.data(), map.SizeT);
    const double range[2] = { map.TimeValues.front(), map.TimeValues.back() };
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  }
  return "";
}

//------------------------------------------------------------------------------
int vtkCheckedTIFFReader::ReadPlanes(vtkInformation* outInfo)
{
  const vtkInternals& in = *this->Internals;
  const mcv::TiffPlaneMap& map = in.Map;
  vtkImageData* output = vtkImageData::GetData(outInfo);
  int extent[6];
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent);
  double spacing[3];
  outInfo->Get(vtkDataObject::SPACING(), spacing);
  output->Initialize();
  output->SetExtent(extent);
  output->SetSpacing(spacing);
  output->SetOrigin(this->GetDataOrigin());

  // The frame: the last whose time is at or before the requested time (as ParaView's
  // readers snap), the first before it.
  int frame = 0;
  if (map.SizeT > 1 && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    const double time = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    for (int t = 0; t < map.SizeT; ++t)
    {
      frame = map.TimeValues[t] <= time ? t : frame;
    }
  }
  if (map.SizeT > 1)
  {
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), map.TimeValues[frame]);
  }

  const int nx = extent[1] - extent[0] + 1;
  const int ny = extent[3] - extent[2] + 1;
  const int nz = extent[5] - extent[4] + 1;
  const bool empty = nx <= 0 || ny <= 0 || nz <= 0;
  const vtkIdType voxels = empty ? 0 : static_cast<vtkIdType>(nx) * ny * nz;
  const int type = vtkTypeOf(in.Bits, in.Format);
  const std::size_t sample = static_cast<std::size_t>(in.Bits / 8);
  std::vector<vtkSmartPointer<vtkDataArray>> arrays;
  for (int c = 0; c < map.SizeC; ++c)
  {
    vtkSmartPointer<vtkDataArray> array =
      vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(type));
    array->SetName(map.ChannelNames[c].c_str());
    array->SetNumberOfTuples(voxels);
    arrays.push_back(array);
  }

  // The pages of the requested slices of this frame, one file open at a time.
  const std::size_t width = static_cast<std::size_t>(map.SizeX);
  const std::size_t height = static_cast<std::size_t>(map.SizeY);
  std::vector<unsigned char> page(empty ? 0 : width * height * sample);
  TIFF* tiff = nullptr;
  int openFile = -1;
  bool ok = true;
  for (int z = extent[4]; ok && !empty && z <= extent[5]; ++z)
  {
    for (int c = 0; ok && c < map.SizeC; ++c)
    {
      const mcv::TiffPlaneRef& ref = map.At(c, z, frame);
      const std::string& path = in.Paths[ref.File];
      if (ref.File != openFile)
      {
        if (tiff)
        {
          TIFFClose(tiff);
        }
        tiff = TIFFOpen(path.c_str(), "r");
        openFile = ref.File;
      }
      std::string problem = tiff ? "" : "cannot be opened by libtiff";
      if (problem.empty() &&
        !TIFFSetSubDirectory(tiff, in.Directories[ref.File][static_cast<std::size_t>(ref.Page)]))
      {
        problem = "has no page " + std::to_string(ref.Page + 1) + " that libtiff can read";
      }
      if (problem.empty())
      {
        problem = readPage(tiff, width, height, sample, static_cast<std::size_t>(extent[2]),
          static_cast<std::size_t>(extent[3]), page.data());
      }
      if (!problem.empty())
      {
        vtkErrorMacro(<< "'" << path << "' " << problem << " (channel " << c + 1 << ", slice "
                      << z + 1 << ", frame " << frame + 1 << ")");
        ok = false;
        break;
      }
      // Row r of a page is y = r (as vtkTIFFReader reads these files).
      auto* out = static_cast<unsigned char*>(arrays[c]->GetVoidPointer(0));
      for (int y = extent[2]; y <= extent[3]; ++y)
      {
        const unsigned char* from = page.data() + (y * width + extent[0]) * sample;
        unsigned char* to = out +
          ((static_cast<std::size_t>(z - extent[4]) * ny + (y - extent[2])) * nx) * sample;
        std::memcpy(to, from, nx * sample);
      }
    }
  }
  if (tiff)
  {
    TIFFClose(tiff);
  }
  if (!ok)
  {
    return 0;
  }
  for (int c = 0; c < map.SizeC; ++c)
  {
    output->GetPointData()->AddArray(arrays[c]);
  }
  output->GetPointData()->SetActiveScalars(map.ChannelNames[0].c_str());
  for (const auto& unit : { std::make_pair("LengthUnit", map.LengthUnit),
         std::make_pair("TimeUnit", map.TimeUnit) })
  {
    vtkNew<vtkStringArray> text;
    text->SetName(unit.first);
    text->InsertNextValue(unit.second);
    output->GetFieldData()->AddArray(text);
  }
  return 1;
}


//------------------------------------------------------------------------------
std::string vtkCheckedTIFFReader::Contents()
{
  return this->Internals->Contents;
}

//------------------------------------------------------------------------------
int vtkCheckedTIFFReader::Frames()
{
  return this->Internals->HasMap ? this->Internals->Map.SizeT : 1;
}
