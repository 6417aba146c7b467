/**
 * @class   vtkCheckedNIFTIImageReader
 * @brief   VTK's NIfTI reader that reads a file whole or refuses it.
 *
 * vtkNIFTIImageReader (ParaView 5.11) delivers a truncated file as the full volume (it
 * only logs "truncated"), fills a volume whose header promises more data than the file
 * holds with uninitialised memory, and aborts the process on a header whose dimensions do
 * not fit in memory. Before anything is allocated, this subclass checks the header
 * against the file and the machine: 1 to 5 dimensions, each at least 1; finite, non-zero
 * spacing; the data bytes the header promises present in the file (.nii, .hdr/.img: the
 * file size; .nii.gz/.img.gz: the whole gzip stream decompressed and counted, so a
 * truncated or corrupt stream is caught too); the volume within the memory this process
 * may use. Any failure, and any error the superclass reports while reading, is an error
 * that names the file and the problem, and the output stays empty (CheckedReading.h).
 *
 * The point array read is named after the file ("ch2" for ch2.nii.gz, mcvFileNames.h)
 * instead of the superclass's name for every file, so that channels merged from several
 * files keep apart. Inside ParaView's vtkFileSeriesReader (the plugin's reader proxy: a list
 * of files is a time series), the array is named after the series ("vol" for vol_0,
 * vol_1, ...) at every step, and a file whose grid differs from the first file's (the grid
 * the series announced) is refused with an error naming both (CheckedReading.h).
 *
 * An atlas's label file beside the volume (MRIcron's aal.nii.txt beside aal.nii.gz: one
 * "<value> <name>" per line) is attached as the field array `<channel>_labels`, the
 * names of its values (mcvLabelTables.h), which the probe shows.
 */
#ifndef vtkCheckedNIFTIImageReader_h
#define vtkCheckedNIFTIImageReader_h

#include "mcvCheckedReaderMacros.h" // for mcvCheckedHeaderReaderMacro
#include "mcvIOVolPackModule.h"      // for export macro
#include "vtkNIFTIImageReader.h"

#include <string> // for std::string

class MCVIOVOLPACK_EXPORT vtkCheckedNIFTIImageReader : public vtkNIFTIImageReader
{
public:
  static vtkCheckedNIFTIImageReader* New();
  vtkTypeMacro(vtkCheckedNIFTIImageReader, vtkNIFTIImageReader);

  // The checks before reading and the header check (mcvCheckedReaderMacros.h); Describe():
  // "NIfTI file '<name>'".
  mcvCheckedHeaderReaderMacro(vtkCheckedNIFTIImageReader);
};

#endif
