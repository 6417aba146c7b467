/**
 * @class   vtkCheckedMetaImageReader
 * @brief   VTK's MetaImage reader (.mhd/.raw, .mha) that reads a file whole or refuses it.
 *
 * vtkMetaImageReader (ParaView 5.11) delivers a .raw shorter than its header says, or a
 * truncated compressed stream, as the full volume padded with zeros and without a word;
 * a missing .raw as a zero-filled volume (with an error); a spacing of 0 as it is; a
 * header it cannot parse (spacing NaN, unknown ElementType, NDims 7) as one voxel; and it
 * aborts the process on a negative or huge DimSize. Before anything is allocated, this
 * subclass reads the header itself and checks it against the data file and the machine:
 * NDims 1 to 3, DimSize of NDims integers >= 1, finite non-zero ElementSpacing, a known
 * ElementType, every data file (LOCAL, a file name, LIST or a %d pattern) present and
 * holding the bytes the header promises (compressed data: the zlib stream decompressed and
 * counted), and the volume within the memory this process may use. Any failure, and any
 * error the superclass reports while reading, is an error that names the file and the
 * problem, and the output stays empty (CheckedReading.h). ASCII data (BinaryData = False)
 * is not counted against its file.
 *
 * The point array read is named after the file ("ch2" for ch2.nii.gz, mcvFileNames.h)
 * instead of the superclass's name for every file, so that channels merged from several
 * files keep apart. Inside ParaView's vtkFileSeriesReader (the plugin's reader proxy: a list
 * of files is a time series), the array is named after the series ("vol" for vol_0,
 * vol_1, ...) at every step, and a file whose grid differs from the first file's (the grid
 * the series announced) is refused with an error naming both (CheckedReading.h).
 */
#ifndef vtkCheckedMetaImageReader_h
#define vtkCheckedMetaImageReader_h

#include "mcvCheckedReaderMacros.h" // for mcvCheckedHeaderReaderMacro
#include "mcvIOVolPackModule.h"      // for export macro
#include "vtkMetaImageReader.h"

#include <string> // for std::string

class MCVIOVOLPACK_EXPORT vtkCheckedMetaImageReader : public vtkMetaImageReader
{
public:
  static vtkCheckedMetaImageReader* New();
  vtkTypeMacro(vtkCheckedMetaImageReader, vtkMetaImageReader);

  // The checks before reading and the header check (mcvCheckedReaderMacros.h); Describe():
  // "MetaImage file '<name>'".
  mcvCheckedHeaderReaderMacro(vtkCheckedMetaImageReader);
};

#endif
