/**
 * @class   vtkCheckedTIFFReader
 * @brief   VTK's TIFF reader that reads a multi-page file or a stack of files whole or
 *          refuses it.
 *
 * vtkTIFFReader (ParaView 5.11) reads a cut multi-page file as a smaller volume of the
 * pages before the cut, without a word; a page whose strips end beyond the file as a
 * volume of whatever its buffer held (with an error); a slice of a stack that is cut, of
 * random bytes or of another size as a black or wrong slice of the stack; and it aborts the
 * process on pages too large for memory. Before anything is allocated, this subclass walks
 * the page directories of every file itself (TiffDirectories.h) and checks: a TIFF header;
 * every directory and every strip or tile inside the file; as many pages as the PageNumber
 * tags count; pages of at least 1 x 1 pixels and 8, 16 or 32 bits per sample; all pages
 * (and all files of a stack) of one size and type; uncompressed pages holding all their
 * pixels; a finite, non-zero spacing; the volume within the memory this process may use.
 * Any failure, and any error the superclass reports while reading (a corrupt compressed
 * strip), is an error that names the file and the problem, and the output stays empty
 * (CheckedReading.h).
 *
 * One file: its pages are the slices (as vtkTIFFReader reads them). Several files
 * (AddFileName, the FileNames property in ParaView) of one page each: one slice each, in
 * the order given, as ParaView's TIFF Series Reader with ReadAsImageStack. Several files
 * whose first holds a volume (several pages, or an ImageJ hyperstack or OME-TIFF) are a
 * time series instead, as ParaView's readers of other formats take a list of files: time
 * step i (time value i) is file i, read by a reader of its own when that step is asked for;
 * every file must hold one frame of the same grid and channels (an error names the file
 * that does not). A list whose first file is an OME-TIFF naming the others as parts of
 * one image (a multi-file OME-TIFF set) is that image, read from its first file.
 *
 * Two kinds of file hold channels and time points in their pages, and say so in the
 * ImageDescription of their first page:
 * - an ImageJ hyperstack (ImageJ/Fiji, tifffile's imagej=True; ImageJHyperstack.h), and
 * - an OME-TIFF (Bio-Formats, Fiji's OME-TIFF export, tifffile's ome=True; one file, or a
 *   set of files in one folder named by the OME-XML; OMETiffMetadata.h).
 * Their pages are mapped to planes (TiffPlaneMap.h) and read with libtiff (any compression
 * it decodes, strips or tiles): one point array per channel, named after the file's channel
 * names (C1, C2... when it has none); the file's voxel spacing (ImageJ: in its unit; OME:
 * in µm), the unit in the field data arrays LengthUnit and TimeUnit; frames as time steps
 * (TIME_STEPS, from the frame interval, else 0, 1, 2...), of which each update reads only
 * the requested frame, and only the slices of the requested extent (a process of a
 * parallel run reads its own slab). The memory check counts one frame.
 */
#ifndef vtkCheckedTIFFReader_h
#define vtkCheckedTIFFReader_h

#include "mcvCheckedReaderMacros.h" // for mcvCheckedReaderMembersMacro
#include "mcvIOVolPackModule.h"      // for export macro
#include "vtkSmartPointer.h" // for vtkSmartPointer
#include "vtkTIFFReader.h"

#include <string> // for std::string
#include <vector> // for std::vector

class MCVIOVOLPACK_EXPORT vtkCheckedTIFFReader : public vtkTIFFReader
{
public:
  static vtkCheckedTIFFReader* New();
  vtkTypeMacro(vtkCheckedTIFFReader, vtkTIFFReader);

  ///@{
  /**
   * The files to read: one multi-page file, or the 2D slices of a stack in order (ParaView
   * sets them one by one through its repeatable FileNames property).
   */
  void AddFileName(VTK_FILEPATH const char* name);
  void RemoveAllFileNames();
  ///@}

  /**
   * As vtkTIFFReader, and also a TIFF that is cut or broken (its error then says why),
   * OME-TIFF files (.ome.tif, .ome.tiff) included.
   */
  int CanReadFile(VTK_FILEPATH const char* name) override;

protected:
  vtkCheckedTIFFReader();
  ~vtkCheckedTIFFReader() override;

  // The checks before reading (mcvCheckedReaderMacros.h); Describe(): "TIFF file '<name>'" or "TIFF stack of N files".
  mcvCheckedReaderMembersMacro();

private:
  vtkCheckedTIFFReader(const vtkCheckedTIFFReader&) = delete;
  void operator=(const vtkCheckedTIFFReader&) = delete;

  // The files named by FileName or FileNames.
  std::vector<std::string> Files();
  // "" when every file holds what its directories promise; else what is wrong.
  std::string CheckFiles();
  // RequestInformation and RequestData of a file read through its plane map.
  std::string PlaneMapInformation(vtkInformation* outInfo);
  int ReadPlanes(vtkInformation* outInfo);

  // A time series of volume files (one file per step, vtkCheckedTIFFReaderSeries.cxx).
  // ClassifyList sets Series and OneImageSet from the listed files' first (its pages and
  // OME-XML); a step is read by a reader of its own (StepReader: this reader's spacing
  // settings), for the series' information and for the step RequestData asks for.
  void ClassifyList();
  vtkSmartPointer<vtkCheckedTIFFReader> StepReader(const std::string& file);
  std::string SeriesInformation(vtkInformation* outInfo);
  int ReadSeriesStep(vtkInformation* outInfo);
  // What one file holds besides its grid: its channels and sample type ("channels DAPI, GFP
  // of uint16"), or its pages' pixels; and its frames.
  std::string Contents();
  int Frames();

  std::vector<std::string> Stack;
  bool Series = false;      // the listed files are a time series of volumes
  bool OneImageSet = false; // the listed files are the parts of one OME-TIFF: read the first
  class vtkInternals;
  vtkInternals* Internals;
};

#endif
