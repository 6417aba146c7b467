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

#include <algorithm>
#include <utility>

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
void vtkGaussianTFVolumeMapper::SetTransferFunctionTable(
  std::vector<std::uint16_t>&& texels, const int dims[3])
{
  // A new table each widget edit: no comparison (the caller bakes only when needed).
  this->TransferFunctionTable = std::move(texels);
  std::copy(dims, dims + 3, this->TransferFunctionTableDims);
  this->TransferFunctionTableTime.Modified();
}

namespace
{
// A texture object of `window` in `texture` (a new one for a new context), and whether its
// data must be uploaded.
bool prepareTexture(vtkSmartPointer<vtkTextureObject>& texture, vtkOpenGLRenderWindow* window,
  vtkTimeStamp& uploadTime, const vtkTimeStamp& dataTime)
{
  if (!texture || texture->GetContext() != window)
  {
    texture = vtkSmartPointer<vtkTextureObject>::New();
    texture->SetContext(window);
    uploadTime = vtkTimeStamp();
  }
  return uploadTime < dataTime;
}
} // namespace

//------------------------------------------------------------------------------
bool vtkGaussianTFVolumeMapper::ActivateTables(vtkOpenGLRenderWindow* window)
{
  bool any = false;
  if (!this->WidgetTable.empty())
  {
    if (prepareTexture(
          this->WidgetTableTexture, window, this->WidgetTableUploadTime, this->WidgetTableTime))
    {
      vtkTextureObject* texture = this->WidgetTableTexture;
      texture->SetMinificationFilter(vtkTextureObject::Nearest);
      texture->SetMagnificationFilter(vtkTextureObject::Nearest);
      texture->SetWrapS(vtkTextureObject::ClampToEdge);
      texture->SetWrapT(vtkTextureObject::ClampToEdge);
      texture->SetWrapR(vtkTextureObject::ClampToEdge);
      // One slice of a 3D texture: the shader's samplers are all 3D (mcvGaussianTFShader).
      texture->Create3DFromRaw(mcv::bricks::TableWidth, this->WidgetTableHeight, 1, 2, VTK_FLOAT,
        this->WidgetTable.data());
      this->WidgetTableUploadTime.Modified();
    }
    this->WidgetTableTexture->Activate();
    any = true;
  }
  if (!this->TransferFunctionTable.empty())
  {
    if (prepareTexture(this->TransferFunctionTableTexture, window,
          this->TransferFunctionTableUploadTime, this->TransferFunctionTableTime))
    {
      vtkTextureObject* texture = this->TransferFunctionTableTexture;
      texture->SetMinificationFilter(vtkTextureObject::Linear);
      texture->SetMagnificationFilter(vtkTextureObject::Linear);
      texture->SetWrapS(vtkTextureObject::ClampToEdge);
      texture->SetWrapT(vtkTextureObject::ClampToEdge);
      texture->SetWrapR(vtkTextureObject::ClampToEdge);
      const int* dims = this->TransferFunctionTableDims;
      // 16-bit normalised RGBA (GL_RGBA16): vtkTextureObject's default for 4 x uint16.
      texture->Create3DFromRaw(dims[0], dims[1], dims[2], 4, VTK_UNSIGNED_SHORT,
        this->TransferFunctionTable.data());
      this->TransferFunctionTableUploadTime.Modified();
    }
    this->TransferFunctionTableTexture->Activate();
    any = true;
  }
  return any;
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeMapper::DeactivateTables()
{
  if (!this->WidgetTable.empty() && this->WidgetTableTexture)
  {
    this->WidgetTableTexture->Deactivate();
  }
  if (!this->TransferFunctionTable.empty() && this->TransferFunctionTableTexture)
  {
    this->TransferFunctionTableTexture->Deactivate();
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
  if (!this->RenderShaderProperty || !window || !this->ActivateTables(window))
  {
    this->Superclass::Render(ren, vol);
    return;
  }
  this->Superclass::Render(ren, vol);
  // The ray caster's program is still bound: a sampler that reads another unit (a new
  // program reads unit 0) drew nothing (the shader checks each table); point it at its
  // table and draw again.
  GLint program = 0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &program);
  if (program > 0)
  {
    bool changed = false;
    const std::pair<const char*, vtkTextureObject*> samplers[2] = {
      { mcv::shader::BrickTable, this->WidgetTable.empty() ? nullptr : this->WidgetTableTexture.Get() },
      { mcv::shader::TransferFunctionTable,
        this->TransferFunctionTable.empty() ? nullptr : this->TransferFunctionTableTexture.Get() }
    };
    for (const auto& sampler : samplers)
    {
      const GLint location = sampler.second ? glGetUniformLocation(program, sampler.first) : -1;
      if (location >= 0)
      {
        const int unit = sampler.second->GetTextureUnit();
        GLint current = -1;
        glGetUniformiv(program, location, &current);
        if (current != unit)
        {
          glUniform1i(location, unit);
          changed = true;
        }
      }
    }
    if (changed)
    {
      this->Superclass::Render(ren, vol);
    }
  }
  this->DeactivateTables();
}

//------------------------------------------------------------------------------
void vtkGaussianTFVolumeMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  if (this->WidgetTableTexture)
  {
    this->WidgetTableTexture->ReleaseGraphicsResources(window);
    this->WidgetTableTexture = nullptr;
  }
  if (this->TransferFunctionTableTexture)
  {
    this->TransferFunctionTableTexture->ReleaseGraphicsResources(window);
    this->TransferFunctionTableTexture = nullptr;
  }
  this->Superclass::ReleaseGraphicsResources(window);
}
