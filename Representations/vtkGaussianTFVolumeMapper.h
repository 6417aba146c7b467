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
 * It also binds the per-sample shader's tables for the render: the widget table
 * (mcvGaussianTFBricks.h: which widgets reach each brick of the volume, a float texture
 * of one slice)
 * and the baked transfer function (mcvGaussianTFTable.h, a 16-bit RGBA 3D texture with
 * linear filtering), and points the shader's samplers at them: VTK's custom uniforms have
 * no sampler type, so the samplers are set on the ray caster's program after its first
 * frame (that frame draws nothing, the shader checks each table, and is rendered again).
 */

#ifndef vtkGaussianTFVolumeMapper_h
#define vtkGaussianTFVolumeMapper_h

#include "mcvRepresentationsGaussianTFModule.h" // for export macro
#include "vtkMultiBlockVolumeMapper.h"
#include "vtkSmartPointer.h" // for the shader properties
#include "vtkTimeStamp.h"    // for the widget table's upload

#include <cstdint> // for the baked table
#include <vector>  // for the tables

class vtkOpenGLRenderWindow;
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

  /**
   * The baked transfer function (mcvGaussianTFTable.h): 4 x uint16 per texel, dims[0] x
   * dims[1] x dims[2] texels (the check slice included); empty: none.
   */
  void SetTransferFunctionTable(std::vector<std::uint16_t>&& texels, const int dims[3]);

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
  // Binds the textures whose data is set (uploading what changed) before a render, and
  // releases them after it.
  bool ActivateTables(vtkOpenGLRenderWindow* window);
  void DeactivateTables();

  std::vector<float> WidgetTable;
  int WidgetTableHeight = 0;
  vtkTimeStamp WidgetTableTime;
  vtkTimeStamp WidgetTableUploadTime;
  vtkSmartPointer<vtkTextureObject> WidgetTableTexture;

  std::vector<std::uint16_t> TransferFunctionTable;
  int TransferFunctionTableDims[3] = { 0, 0, 0 };
  vtkTimeStamp TransferFunctionTableTime;
  vtkTimeStamp TransferFunctionTableUploadTime;
  vtkSmartPointer<vtkTextureObject> TransferFunctionTableTexture;
};

#endif
