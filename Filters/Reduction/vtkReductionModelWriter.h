/**
 * @class   vtkReductionModelWriter
 * @brief   writes the reduction model a DimensionReduction fitted (`.mcvmodel`).
 *
 * Input: the Spectrum output (port 1) of vtkDimensionReduction, whose field data carries
 * the model file's bytes as the array `ReductionModel` when the reduction computed its
 * features from the channels (the fused path; a reduction of an input Features array has
 * no model: its normalisation is not known here). The bytes are checked (format, checksum,
 * sizes) and written to a temporary name in the same folder that is renamed into place,
 * so no half-written model ever carries FileName. In a parallel run only process 0 writes
 * (the table is piece 0's).
 *
 * In ParaView: File > Save Data on DimensionReduction's Spectrum output, or
 * multichannel_explorer.save_model(reduction, path). mcvReductionModelFile.h documents
 * the format.
 */

#ifndef vtkReductionModelWriter_h
#define vtkReductionModelWriter_h

#include "mcvFiltersReductionModule.h" // for export macro
#include "vtkWriter.h"

class MCVFILTERSREDUCTION_EXPORT vtkReductionModelWriter : public vtkWriter
{
public:
  static vtkReductionModelWriter* New();
  vtkTypeMacro(vtkReductionModelWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The file to write (conventionally `.mcvmodel`). */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

protected:
  vtkReductionModelWriter() = default;
  ~vtkReductionModelWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  char* FileName = nullptr;

private:
  vtkReductionModelWriter(const vtkReductionModelWriter&) = delete;
  void operator=(const vtkReductionModelWriter&) = delete;
};

#endif
