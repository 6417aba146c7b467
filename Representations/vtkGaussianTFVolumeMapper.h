/**
 * @class   vtkGaussianTFVolumeMapper
 * @brief   the volume mapper of the "Gaussian TF Volume" representation.
 *
 * ParaView's multi-block volume mapper, plus one thing: the shader property of the
 * representation (the per-sample Gaussian transfer function's shader replacements and
 * uniforms) is given to the volume that is actually rendered. ParaView renders through a
 * vtkPVLODVolume whose inner vtkLODProp3D volumes do not take the outer prop's shader
 * property, and the mapper is the one place that sees the inner volume at render time.
 *
 * It also binds the per-sample shader's widget table (mcvGaussianTFBricks.h: which widgets
 * reach each brick of the volume) as a float texture for the render, and points the
 * shader's sampler at it: VTK's custom uniforms have no sampler type, so the sampler is
 * set on the ray caster's program after its first frame (that frame draws nothing, the
 * shader checks the table, and is rendered again).
 */

#ifndef vtkGaussianTFVolumeMapper_h
#define vtkGaussianTFVolumeMapper_h

#include "mcvRepresentationsGaussianTFModule.h" // for export macro
#include "vtkMultiBlockVolumeMapper.h"
#include "vtkSmartPointer.h" // for the shader properties
#include "vtkTimeStamp.h"    // for the widget table's upload

#include <vector> // for the widget table

class vtkShaderProperty;
class vtkTextureObject;

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

  /**
   * The widget table (2 floats per entry, mcv::bricks::TableWidth entries per row, `height`
   * rows); empty: none (the shader then has no table either).
   */
  void SetWidgetTable(const std::vector<float>& table, int height);

  void Render(vtkRenderer* ren, vtkVolume* vol) override;
  void ReleaseGraphicsResources(vtkWindow* window) override;

protected:
  vtkGaussianTFVolumeMapper();
  ~vtkGaussianTFVolumeMapper() override;

private:
  vtkGaussianTFVolumeMapper(const vtkGaussianTFVolumeMapper&) = delete;
  void operator=(const vtkGaussianTFVolumeMapper&) = delete;

  vtkSmartPointer<vtkShaderProperty> RenderShaderProperty;
  vtkSmartPointer<vtkShaderProperty> PlainShaderProperty; // no replacements
  std::vector<float> WidgetTable;
  int WidgetTableHeight = 0;
  vtkTimeStamp WidgetTableTime;
  vtkTimeStamp WidgetTableUploadTime;
  vtkSmartPointer<vtkTextureObject> WidgetTableTexture;
};

#endif
