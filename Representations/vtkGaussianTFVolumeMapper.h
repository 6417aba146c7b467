/**
 * @class   vtkGaussianTFVolumeMapper
 * @brief   the volume mapper of the "Gaussian TF Volume" representation.
 *
 * ParaView's multi-block volume mapper, plus one thing: the shader property of the
 * representation (the per-sample Gaussian transfer function's shader replacements and
 * uniforms) is given to the volume that is actually rendered. ParaView renders through a
 * vtkPVLODVolume whose inner vtkLODProp3D volumes do not take the outer prop's shader
 * property, and the mapper is the one place that sees the inner volume at render time.
 */

#ifndef vtkGaussianTFVolumeMapper_h
#define vtkGaussianTFVolumeMapper_h

#include "mcvRepresentationsGaussianTFModule.h" // for export macro
#include "vtkMultiBlockVolumeMapper.h"
#include "vtkSmartPointer.h" // for the shader properties

class vtkShaderProperty;

class MCVREPRESENTATIONSGAUSSIANTF_EXPORT vtkGaussianTFVolumeMapper
  : public vtkMultiBlockVolumeMapper
{
public:
  static vtkGaussianTFVolumeMapper* New();
  vtkTypeMacro(vtkGaussianTFVolumeMapper, vtkMultiBlockVolumeMapper);

  /**
   * The shader property given to the rendered volume; nullptr: none (VTK's own ray
   * caster, as for per-voxel colours).
   */
  void SetRenderShaderProperty(vtkShaderProperty* property);

  void Render(vtkRenderer* ren, vtkVolume* vol) override;

protected:
  vtkGaussianTFVolumeMapper();
  ~vtkGaussianTFVolumeMapper() override;

private:
  vtkGaussianTFVolumeMapper(const vtkGaussianTFVolumeMapper&) = delete;
  void operator=(const vtkGaussianTFVolumeMapper&) = delete;

  vtkSmartPointer<vtkShaderProperty> RenderShaderProperty;
  vtkSmartPointer<vtkShaderProperty> PlainShaderProperty; // no replacements
};

#endif
