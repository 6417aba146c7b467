#include "vtkCheckedTIFFReader.h"

#include "CheckedReading.h"
#include "TiffDirectories.h"

#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkStringArray.h"
#include "vtk_tiff.h"
#include "vtksys/SystemTools.hxx"

#include <cstdarg>
#include <cstdio>
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
  const std::string lower = vtksys::SystemTools::LowerCase(name ? name : "");
  for (const char* ome : { ".ome.tif", ".ome.tiff" })
  {
    const std::string tail = ome;
    if (lower.size() > tail.size() && lower.compare(lower.size() - tail.size(), tail.size(), tail) == 0)
    {
      return 0;
    }
  }
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
    if (!problem.empty())
    {
      return which.str() + problem;
    }
    first = i == 0 ? pages[0] : first;
    slices += files.size() > 1 ? 1.0 : static_cast<double>(pages.size());
  }
  return mcv::checkFitsInMemory(static_cast<double>(first.Width) * first.Height * slices,
    first.SamplesPerPixel * first.BitsPerSample / 8.0);
}

//------------------------------------------------------------------------------
int vtkCheckedTIFFReader::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The files first: libtiff would stop quietly at a cut directory.
  this->Refused = !mcv::checkedRequestInformation(this, outputVector, this->Describe(), [&] {
    const std::string problem = this->CheckFiles();
    if (!problem.empty())
    {
      return problem;
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
    const int ok = this->Superclass::RequestData(request, inputVector, outputVector);
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
    return "TIFF stack of " + std::to_string(files.size()) + " files";
  }
  return "TIFF file '" + (files.empty() ? std::string() : files[0]) + "'";
}
