/**
 * @class   vtkVolumeFileReader
 * @brief   the base of the suite's own readers: one volume from a file or folder.
 *
 * A source (no input, one vtkImageData output) that reads FileName. Subclasses say which
 * files they read (CanReadFile, the ParaView reader factory asks it) and read them in
 * RequestInformation and RequestData.
 */

#ifndef vtkVolumeFileReader_h
#define vtkVolumeFileReader_h

#include "mcvIOVolPackModule.h" // for export macro
#include "vtkImageAlgorithm.h"

class MCVIOVOLPACK_EXPORT vtkVolumeFileReader : public vtkImageAlgorithm
{
public:
  vtkTypeMacro(vtkVolumeFileReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The file (or folder) to read. */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  /** 1 when `name` looks like a file of this reader's format, else 0. */
  virtual int CanReadFile(VTK_FILEPATH const char* name) = 0;

protected:
  vtkVolumeFileReader();
  ~vtkVolumeFileReader() override;

  char* FileName = nullptr;

private:
  vtkVolumeFileReader(const vtkVolumeFileReader&) = delete;
  void operator=(const vtkVolumeFileReader&) = delete;
};

#endif
