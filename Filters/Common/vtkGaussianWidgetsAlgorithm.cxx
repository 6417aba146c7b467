#include "vtkGaussianWidgetsAlgorithm.h"

#include "GaussianTransferFunction.h"
#include "mcvWidgetValues.h"

struct vtkGaussianWidgetsAlgorithm::vtkInternals
{
  mcv::vtkhelpers::WidgetValues GaussianWidgets;
};

vtkGaussianWidgetsAlgorithm::vtkGaussianWidgetsAlgorithm()
  : Internals(new vtkInternals)
{
}

vtkGaussianWidgetsAlgorithm::~vtkGaussianWidgetsAlgorithm() = default;

void vtkGaussianWidgetsAlgorithm::SetNumberOfGaussianWidgetValues(int count)
{
  if (this->Internals->GaussianWidgets.SetNumber(count))
  {
    this->Modified();
  }
}

void vtkGaussianWidgetsAlgorithm::SetGaussianWidgetValue(int index, double value)
{
  if (this->Internals->GaussianWidgets.Set(index, value))
  {
    this->Modified();
  }
}

int vtkGaussianWidgetsAlgorithm::GetNumberOfGaussianWidgetValues()
{
  return this->Internals->GaussianWidgets.GetNumber();
}

double vtkGaussianWidgetsAlgorithm::GetGaussianWidgetValue(int index)
{
  return this->Internals->GaussianWidgets.Get(index);
}

mcv::WidgetList vtkGaussianWidgetsAlgorithm::ParseGaussianWidgets() const
{
  return mcv::parseGaussianWidgets(
    this->Internals->GaussianWidgets.Data(), this->Internals->GaussianWidgets.Size());
}

void vtkGaussianWidgetsAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "GaussianWidgets: " << this->Internals->GaussianWidgets.Size() / 8 << "\n";
}
