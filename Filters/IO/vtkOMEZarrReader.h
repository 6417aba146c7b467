/**
 * @class   vtkOMEZarrReader
 * @brief   reads an OME-Zarr image (OME-NGFF 0.4, Zarr format 2): a folder `x.ome.zarr`.
 *
 * FileName is the image's folder (the one that holds `.zattrs`).
 *
 * The folder's `.zattrs` holds `multiscales[0]`: the axes (a subset of t, c, z, y, x in that
 * order; a y, x image is a volume of one slice) and the resolution levels (`datasets`, finest
 * first), each a Zarr array in its own folder with a scale and a translation per axis
 * (`coordinateTransformations`, the multiscale's own applied after the level's). The
 * output is image data on the z, y, x grid of the level read: spacing and origin are the
 * level's scale and translation; each channel (index along c) is one point array named after
 * `omero.channels[i].label` (else C1..Cn; made unique), of the array's type. The t axis
 * gives the time steps (index * scale + translation); each update reads one time point.
 *
 * Only the chunks that meet the requested extent are read (the reader can produce any
 * sub-extent: ParaView's pieces, in parallel, each read their own part); a chunk file that
 * is absent holds the array's fill value (the Zarr specification).
 *
 * Field data of the output: `LengthUnit` (the unit of the spatial axes, "" when none),
 * `TimeUnit`, `ChannelColors` (omero's hex colour of each array, "" when none),
 * `ResolutionLevel` (the level read) and `BytesRead` (bytes of the chunk files this
 * process read for this output; decompressed bytes are not counted).
 *
 * Refused, with one error that names the folder and the problem and an empty output: a
 * folder without OME-Zarr metadata, a level that does not exist or has no `.zarray`, a
 * dtype, compressor, filter or order that cannot be read, a shape that disagrees with the
 * axes, a chunk that does not decode or decodes to the wrong size, a volume that does not
 * fit in memory (CheckedReading.h).
 */

#ifndef vtkOMEZarrReader_h
#define vtkOMEZarrReader_h

#include "mcvIOVolPackModule.h" // for export macro
#include "vtkVolumeFileReader.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class MCVIOVOLPACK_EXPORT vtkOMEZarrReader : public vtkVolumeFileReader
{
public:
  static vtkOMEZarrReader* New();
  vtkTypeMacro(vtkOMEZarrReader, vtkVolumeFileReader);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The resolution level to read: 0 is the finest (full resolution), 1 the next coarser,
   * and so on. -1 (the default): the finest level whose one time point fits in the memory
   * this process may use (MemoryBudget). The whole level is counted, also when several
   * processes share it: every process must choose the same level, and what one process
   * sees of the others' memory is not known when the level is chosen. RequestData checks
   * the extent it is asked for.
   */
  vtkSetMacro(ResolutionLevel, int);
  vtkGetMacro(ResolutionLevel, int);
  ///@}

  /** The level chosen by the last RequestInformation (-1 when none could be). */
  vtkGetMacro(LevelRead, int);

  /** The number of resolution levels of the image (0 until its metadata was read). */
  vtkGetMacro(NumberOfLevels, int);

  /** Bytes of chunk files read by the last RequestData (this process's). */
  vtkGetMacro(BytesRead, vtkTypeInt64);

  /**
   * 1 when `name` is a folder with Zarr metadata (`.zattrs`, `.zgroup` or `.zarray`), else
   * 0. Whether it is an OME-Zarr image that can be read is for RequestInformation to say.
   */
  int CanReadFile(VTK_FILEPATH const char* name) override;

protected:
  vtkOMEZarrReader();
  ~vtkOMEZarrReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int ResolutionLevel = -1;
  int LevelRead = -1;
  int NumberOfLevels = 0;
  vtkTypeInt64 BytesRead = 0;

private:
  vtkOMEZarrReader(const vtkOMEZarrReader&) = delete;
  void operator=(const vtkOMEZarrReader&) = delete;

  // "OME-Zarr folder '<FileName>'", the subject of every message.
  std::string Describe() const;

  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
