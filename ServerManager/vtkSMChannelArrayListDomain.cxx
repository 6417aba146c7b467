#include "vtkSMChannelArrayListDomain.h"

#include "vtkObjectFactory.h"
#include "vtkSMStringVectorProperty.h"

#include <string>
#include <vector>

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
  this->Superclass::Update(requestingProperty);
  auto* property = vtkSMStringVectorProperty::SafeDownCast(this->GetProperty());
  if (!property)
  {
    return;
  }
  auto values = [property](bool unchecked) {
    std::vector<std::string> list;
    const unsigned int n =
      unchecked ? property->GetNumberOfUncheckedElements() : property->GetNumberOfElements();
    for (unsigned int i = 0; i < n; ++i)
    {
      const char* value =
        unchecked ? property->GetUncheckedElement(i) : property->GetElement(i);
      list.emplace_back(value ? value : "");
    }
    return list;
  };
  const std::vector<std::string> checked = values(false);
  const bool empty = checked.empty() && values(true).empty();
  const bool filledHere = this->Filled && checked == this->FilledValues && values(true) == checked;
  if (!empty && !filledHere)
  {
    return; // the user's (or a state file's) selection
  }
  // Every channel of the current input; none while the input has not run, which the
  // filters read as every channel too. (The superclass's default for a property that holds
  // one element is the active scalars alone.)
  std::vector<std::string> all;
  for (unsigned int i = 0; i < this->GetNumberOfStrings(); ++i)
  {
    all.emplace_back(this->GetString(i));
  }
  if (all != checked)
  {
    property->SetElements(all);
  }
  this->FilledValues = all;
  this->Filled = true;
}

//------------------------------------------------------------------------------
void vtkSMChannelArrayListDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
