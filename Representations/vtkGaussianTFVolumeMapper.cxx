#include "vtkGaussianTFVolumeMapper.h"

#include "mcvGaussianTFBricks.h"
#include "mcvGaussianTFShader.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderProperty.h"
#include "vtkRenderer.h"
#include "vtkTextureObject.h"
#include "vtkVolume.h"
#include "vtk_glew.h"

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
void vtkGaussianTFVolumeMapper::SetWidgetTable(const std::vector<float>& table, int height)
{
  if (table != this->WidgetTable || height != this->WidgetTableHeight)
  {
    this->WidgetTable = table;
    this->WidgetTableHeight = height;
    this->WidgetTableTime.Modified();
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
  auto window = vtkOpenGLRenderWindow::SafeDownCast(ren ? ren->GetRenderWindow() : nullptr);
  if (!this->RenderShaderProperty || this->WidgetTable.empty() || !window)
  {
    this->Superclass::Render(ren, vol);
    return;
  }
  if (!this->WidgetTableTexture || this->WidgetTableTexture->GetContext() != window)
  {
    this->WidgetTableTexture = vtkSmartPointer<vtkTextureObject>::New();
    this->WidgetTableTexture->SetContext(window);
    this->WidgetTableUploadTime = vtkTimeStamp();
  }
  vtkTextureObject* texture = this->WidgetTableTexture;
  if (this->WidgetTableUploadTime < this->WidgetTableTime)
  {
    texture->SetMinificationFilter(vtkTextureObject::Nearest);
    texture->SetMagnificationFilter(vtkTextureObject::Nearest);
    texture->SetWrapS(vtkTextureObject::ClampToEdge);
    texture->SetWrapT(vtkTextureObject::ClampToEdge);
    texture->Create2DFromRaw(mcv::bricks::TableWidth, this->WidgetTableHeight, 2, VTK_FLOAT,
      this->WidgetTable.data());
    this->WidgetTableUploadTime.Modified();
  }
  texture->Activate();
  const int unit = texture->GetTextureUnit();
  this->Superclass::Render(ren, vol);
  // The ray caster's program is still bound: a sampler that reads another unit (a new
  // program reads unit 0) drew nothing (the shader checks the table); point it at the
  // table and draw again.
  GLint program = 0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &program);
  if (program > 0)
  {
    const GLint location = glGetUniformLocation(program, mcv::shader::BrickTable);
    if (location >= 0)
    {
      GLint current = -1;
      glGetUniformiv(program, location, &current);
      if (current != unit)
      {
        glUniform1i(location, unit);
        this->Superclass::Render(ren, vol);
      }
    }
  }
  texture->Deactivate();
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  if (this->WidgetTableTexture)
  {
    this->WidgetTableTexture->ReleaseGraphicsResources(window);
    this->WidgetTableTexture = nullptr;
  }
  this->Superclass::ReleaseGraphicsResources(window);
}
