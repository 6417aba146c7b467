// The GLSL of per-sample classification: the fragment-shader replacements that make VTK's
// GPU ray caster evaluate the Gaussian widgets at every ray sample (dissertation chapter 5,
// the same formula as mcv::applyGaussianWidgets), and the uniforms they read.
//
// The volume texture is the coordinate texture of CoordinateTexture.h (x, y, z, drawn as
// 16-bit normalised values). Two evaluations: the baked table (mcvGaussianTFTable.h: one
// trilinear fetch of a table over the reduced domain per sample, opacity times w as
// below), or every widget at every sample (exact). Per sample t = texture(x, y, z, w):
//   x = min + extent * t.xyz / t.w   (the drawn neighbours' mean: undrawn texels hold 0)
//   alpha_i = a_i exp(-|x - mu_i|^2 / (2 sigma_i^2)),  opacity = (1 - prod(1 - alpha_i)) t.w
//   colour  = sum_i alpha_i c_i / sum_i alpha_i   (where every alpha_i underflows, the
//             opacity is 0 too and the sample is transparent)
// With a widget table (mcvGaussianTFBricks.h) only the widgets of the sample's brick are
// evaluated, and bricks no widget reaches are skipped.
// Composite: opacity per unit length, corrected for the sample distance as VTK corrects
// its opacity tables (1 - (1 - a)^(d / unit)), then front-to-back compositing. Maximum
// intensity: the colour of the most opaque sample of the ray.
#pragma once

#include <string>

namespace mcv
{
namespace shader
{

// Widgets in uniform arrays: 2 x vec4 each, 128 vec4 in all, well inside the 1024 uniform
// components that OpenGL 3.2 (what VTK's ray caster requires) guarantees a fragment shader.
constexpr int MaximumWidgets = 64;

// Uniform names (set through vtkOpenGLShaderProperty::GetFragmentCustomUniforms()).
constexpr const char* WidgetCount = "mcv_widgetCount";       // int
constexpr const char* WidgetCentreK = "mcv_widgetCentreK";   // vec4[64]: mu, 1/(2 sigma^2)
constexpr const char* WidgetColourLogA = "mcv_widgetColourLogA"; // vec4[64]: c, ln a
constexpr const char* CoordinateMin = "mcv_coordinateMin";   // vec3
constexpr const char* CoordinateExtent = "mcv_coordinateExtent"; // vec3
constexpr const char* UnitDistance = "mcv_unitDistance";     // float, world units
constexpr const char* VolumeSize = "mcv_volumeSize";         // vec3, voxels (bricks only)
constexpr const char* BrickGrid = "mcv_brickGrid";           // vec3, bricks (bricks only)
// The widget table's sampler (mcvGaussianTFBricks.h), bound by vtkGaussianTFVolumeMapper.
constexpr const char* BrickTable = "mcv_brickTable";
// The baked table (mcvGaussianTFTable.h): its sampler, bound by vtkGaussianTFVolumeMapper,
// and the map from coordinates t in [0, 1]^3 to its texture coordinates, t * scale + offset.
constexpr const char* TransferFunctionTable = "mcv_tfTable";
constexpr const char* TableScale = "mcv_tableScale";   // vec3: (n - 1) / texture size
constexpr const char* TableOffset = "mcv_tableOffset"; // vec3: 0.5 / texture size

// Appended to //VTK::Shading::Dec: mcvClassify(vec4 texel, int start, int count) -> (rgb,
// opacity) over `count` widgets: those of the table's list at `start`, or (start < 0) the
// first `count`. With `bricks`, the widget table's sampler and look-ups. With `table`,
// mcvClassify reads the baked table instead (every widget, whatever start and count say).
std::string ClassifyDeclaration(bool bricks, bool table);

// Appended to //VTK::Shading::Init (before the first sample): with `jitter`, each ray
// starts a pseudo-random fraction of a step further in, so that samples of neighbouring
// pixels do not lie on the same view-aligned planes (the wood-grain banding).
// With `bricks` (`table`), a ray draws nothing unless the widget (baked) table is bound.
std::string RayStart(bool jitter, bool bricks, bool table);

// Replaces //VTK::Shading::Impl: sample, classify, composite or keep the maximum. With
// `bricks`, only the widgets of the sample's brick, and a brick no widget reaches is
// skipped to its exit (mcvGaussianTFBricks.h).
std::string SampleAndBlend(bool maximumIntensity, bool bricks);

} // namespace shader
} // namespace mcv
