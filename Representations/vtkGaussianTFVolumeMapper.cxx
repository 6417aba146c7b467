#include "vtkGaussianTFVolumeMapper.h"

#include "vtkObjectFactory.h"
#include "vtkOpenGLShaderProperty.h"
#include "vtkVolume.h"

vtkStandardNewMacro(vtkGaussianTFVolumeMapper);

//------------------------------------------------------------------------------
vtkGaussianTFVolumeMapper::vtkGaussianTFVolumeMapper()
  : PlainShaderProperty(vtkSmartPointer<vtkOpenGLShaderProperty>::New())
{
}

//------------------------------------------------------------------------------
vtkGaussianTFVolumeMapper::~vtkGaussianTFVolumeMapper() = default;

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeMapper::SetRenderShaderProperty(vtkShaderProperty* property)
{
  if (this->RenderShaderProperty != property)
  {
    this->RenderShaderProperty = property;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  vtkShaderProperty* wanted =
    this->RenderShaderProperty ? this->RenderShaderProperty.Get() : this->PlainShaderProperty.Get();
  if (vol->GetShaderProperty() != wanted)
  {
    vol->SetShaderProperty(wanted); // the ray caster rebuilds its shader on the change
  }
  this->Superclass::Render(ren, vol);
}
