/**
 * @class   vtkVolPackDenReader
 * @brief   reads VolPack density volumes (.den): a small header, then raw uint8 voxels.
 *
 * Layout (VolPack's examples/denfile.c): a 16-bit version number (1; 0x0100 means the
 * file was written with the other byte order and every header field is byte-swapped),
 * then 27 16-bit fields (original, extracted and map min/max/length triples), a 16-bit
 * warp count and a 32-bit voxel count that must equal the product of the map lengths;
 * then map_len[0] x map_len[1] x map_len[2] unsigned bytes, x fastest. 62 header bytes.
 *
 * The format stores no voxel size: DataSpacing and DataOrigin (default 1 1 1 and 0 0 0)
 * set them. The output is a vtkImageData with one uint8 point array (ScalarArrayName,
 * default "Density") as active scalars. Bad files (not .den, inconsistent header,
 * truncated data) give an error and no output.
 */

#ifndef vtkVolPackDenReader_h
#define vtkVolPackDenReader_h

#include "mcvIOVolPackModule.h" // for export macro
#include "vtkImageAlgorithm.h"

class MCVIOVOLPACK_EXPORT vtkVolPackDenReader : public vtkImageAlgorithm
{
public:
  static vtkVolPackDenReader* New();
  vtkTypeMacro(vtkVolPackDenReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The .den file to read. */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /** World size of a voxel (the format has none; default 1 1 1). */
  vtkSetVector3Macro(DataSpacing, double);
  vtkGetVector3Macro(DataSpacing, double);
  ///@}

  ///@{
  /** World position of voxel (0,0,0) (default 0 0 0). */
  vtkSetVector3Macro(DataOrigin, double);
  vtkGetVector3Macro(DataOrigin, double);
  ///@}

  ///@{
  /** Name of the output point array (default "Density"). */
  vtkSetStringMacro(ScalarArrayName);
  vtkGetStringMacro(ScalarArrayName);
  ///@}

  /**
   * 1 when `fileName` starts as a .den file (its version field), else 0; the rest of the
   * header and the size are checked when it is read, and an error says what is wrong.
   */
  int CanReadFile(VTK_FILEPATH const char* fileName);

  /** Dimensions read from the header by the last RequestInformation. */
  vtkGetVector3Macro(Dimensions, int);

protected:
  vtkVolPackDenReader();
  ~vtkVolPackDenReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  char* ScalarArrayName = nullptr;
  double DataSpacing[3] = { 1.0, 1.0, 1.0 };
  double DataOrigin[3] = { 0.0, 0.0, 0.0 };
  int Dimensions[3] = { 0, 0, 0 };

private:
  // False (with an error naming the file) when DataSpacing is zero or not finite.
  bool CheckSpacing();

  vtkVolPackDenReader(const vtkVolPackDenReader&) = delete;
  void operator=(const vtkVolPackDenReader&) = delete;
};

#endif
