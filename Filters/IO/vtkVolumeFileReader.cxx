#include "vtkVolumeFileReader.h"

//------------------------------------------------------------------------------
vtkVolumeFileReader::vtkVolumeFileReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
vtkVolumeFileReader::~vtkVolumeFileReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkVolumeFileReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}
