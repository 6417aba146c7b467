#include "vtkSMChannelArrayListDomain.h"

#include "vtkObjectFactory.h"
#include "vtkSMStringVectorProperty.h"

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
    mcv::vtkhelpers::isSuiteOutputArray(arrayName) ||
    this->Superclass::IsFilteredArray(info, association, arrayName);
}

//------------------------------------------------------------------------------
void vtkSMChannelArrayListDomain::Update(vtkSMProperty* requestingProperty)
{
  const unsigned int before = this->GetNumberOfStrings();
  this->Superclass::Update(requestingProperty);
  auto* property = vtkSMStringVectorProperty::SafeDownCast(this->GetProperty());
  if (property && before == 0 && this->GetNumberOfStrings() > 0 &&
    property->GetNumberOfElements() == 0 && property->GetNumberOfUncheckedElements() == 0)
  {
    this->SetDefaultValues(property, false);
  }
}

//------------------------------------------------------------------------------
void vtkSMChannelArrayListDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
