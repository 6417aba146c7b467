#include "vtkReductionModelWriter.h"

#include "vtkDataObject.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkUnsignedCharArray.h"

#include "mcvReductionModelFile.h"

#include <vector>

vtkStandardNewMacro(vtkReductionModelWriter);

//------------------------------------------------------------------------------
vtkReductionModelWriter::~vtkReductionModelWriter()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
int vtkReductionModelWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

//------------------------------------------------------------------------------
void vtkReductionModelWriter::WriteData()
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (controller && controller->GetLocalProcessId() > 0)
  {
    return; // process 0 holds the model (DimensionReduction's piece 0) and writes it
  }
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName to write the reduction model to.");
    return;
  }
  vtkDataObject* input = this->GetInput();
  auto* bytes = input
    ? vtkUnsignedCharArray::SafeDownCast(input->GetFieldData()->GetAbstractArray("ReductionModel"))
    : nullptr;
  if (!bytes || bytes->GetNumberOfTuples() == 0)
  {
    vtkErrorMacro("The input carries no reduction model (field data 'ReductionModel'), so "
      << this->FileName
      << " was not written. Connect the Spectrum output of a DimensionReduction that ran without error and "
         "computed its features from the channels (FeatureSet 6D, 24D or Custom, or Automatic without a "
         "Features array): a reduction of an input Features array does not know how those features were "
         "normalised.");
    return;
  }
  const unsigned char* p = bytes->GetPointer(0);
  const std::vector<char> file(p, p + bytes->GetNumberOfTuples());
  mcv::vtkhelpers::ModelFile check;
  std::string error = mcv::vtkhelpers::decodeModel(file, "for " + std::string(this->FileName), check);
  if (!error.empty())
  {
    vtkErrorMacro(<< error << " Nothing was written.");
    return;
  }
  error = mcv::vtkhelpers::writeFileAtomically(this->FileName, file);
  if (!error.empty())
  {
    vtkErrorMacro("The reduction model " << this->FileName << " " << error << ".");
  }
}

//------------------------------------------------------------------------------
void vtkReductionModelWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}
