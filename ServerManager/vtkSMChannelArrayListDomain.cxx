#include "vtkSMChannelArrayListDomain.h"

#include "vtkObjectFactory.h"

#include "../Filters/Common/mcvInternalArrays.h"

vtkStandardNewMacro(vtkSMChannelArrayListDomain);

//------------------------------------------------------------------------------
vtkSMChannelArrayListDomain::vtkSMChannelArrayListDomain() = default;

//------------------------------------------------------------------------------
vtkSMChannelArrayListDomain::~vtkSMChannelArrayListDomain() = default;

//------------------------------------------------------------------------------
bool vtkSMChannelArrayListDomain::IsFilteredArray(
  vtkPVDataInformation* info, int association, const char* arrayName)
{
  return mcv::vtkhelpers::isInternalArray(arrayName) ||
    this->Superclass::IsFilteredArray(info, association, arrayName);
}

//------------------------------------------------------------------------------
void vtkSMChannelArrayListDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
