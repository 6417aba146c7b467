#include "mcvGaussianTFShader.h"

#include "GaussianWidgetFormula.h"
#include "mcvGaussianTFBricks.h"
#include "mcvGaussianTFTable.h"

namespace mcv
{
namespace shader
{

std::string ClassifyDeclaration(bool bricks, bool table)
{
  std::string code = mcv::widgetFormulaGLSL();
  if (bricks)
  {
    code += "#define MCV_TABLE_WIDTH " + std::to_string(bricks::TableWidth) + "\n#define MCV_BRICK " +
      std::to_string(bricks::BrickSize) + ".0\n#define MCV_CHECK " +
      std::to_string(static_cast<int>(bricks::CheckValue)) + ".0\n" + R"GLSL(
// The widget table of mcvGaussianTFBricks.h: (x, y) entries, TableWidth to a row. A 3D
// texture of one slice, as the baked table: until the mapper points the samplers at their
// tables, both read unit 0, which OpenGL allows only for samplers of one type.
uniform sampler3D mcv_brickTable;
vec2 mcvTableEntry(int n)
{
  return texelFetch(mcv_brickTable, ivec3(n % MCV_TABLE_WIDTH, n / MCV_TABLE_WIDTH, 0), 0).xy;
}
)GLSL";
  }
  if (table)
  {
    const auto& check = tftable::CheckTexel;
    code += "#define MCV_TABLE_CHECK vec4(" + std::to_string(check[0] / 65535.0) + ", " +
      std::to_string(check[1] / 65535.0) + ", " + std::to_string(check[2] / 65535.0) + ", " +
      std::to_string(check[3] / 65535.0) + ")\n";
    code += R"GLSL(
// Multichannel Explorer: the Gaussian widgets baked into a 3D table over the reduced domain
// (mcvGaussianTFTable.h), read per sample with linear filtering.
uniform sampler3D mcv_tfTable;
// The table's check slice (its last z slice) holds MCV_TABLE_CHECK: false until the
// sampler reads the table.
bool mcvTableBound()
{
  ivec3 size = textureSize(mcv_tfTable, 0);
  vec4 check = texelFetch(mcv_tfTable, ivec3(0, 0, size.z - 1), 0);
  return size.z > 1 && all(lessThan(abs(check - MCV_TABLE_CHECK), vec4(1.0e-3)));
}
// start and count (the brick table's list) are not needed: the table holds every widget.
vec4 mcvClassify(vec4 texel, int start, int count)
{
  if (texel.w <= 0.0)
  {
    return vec4(0.0);
  }
  vec3 t = clamp(texel.xyz / texel.w, 0.0, 1.0);
  vec4 c = texture(mcv_tfTable, t * mcv_tableScale + mcv_tableOffset);
  return vec4(c.rgb, c.a * texel.w);
}
)GLSL";
    return code;
  }
  code += R"GLSL(
// Multichannel Explorer: Gaussian widgets evaluated per sample.
// Widget i's share of the sample at reduced coordinates x.
void mcvAddWidget(int i, vec3 x, inout float transparency, inout float weightSum,
  inout vec3 colourSum)
{
  vec3 d = x - mcv_widgetCentreK[i].xyz;
  float e = mcvWidgetLogWeight(mcv_widgetColourLogA[i].w, mcv_widgetCentreK[i].w, dot(d, d));
  // The colour weight alpha_i is the opacity's exp(e) (one exp per widget: a software
  // rasteriser runs both sides of a branch, so a log-domain rescaling costs two more).
  float w = exp(e);
  transparency = mcvWidgetTransmit(transparency, w, 1.0);
  weightSum += w;
  colourSum += w * mcv_widgetColourLogA[i].rgb;
}

// start < 0: every widget; else the `count` widgets of the table's list at `start`.
vec4 mcvClassify(vec4 texel, int start, int count)
{
  if (texel.w <= 0.0 || mcv_widgetCount <= 0)
  {
    return vec4(0.0);
  }
  vec3 x = mcv_coordinateMin + mcv_coordinateExtent * (texel.xyz / texel.w);
  float transparency = 1.0;
  float weightSum = 0.0;
  vec3 colourSum = vec3(0.0);
  // Every widget: the index is the same in all the samples a SIMD unit runs together (the
  // loop bound is a uniform; samples of listed bricks leave at once), so the widgets'
  // uniforms are read once, not gathered per sample.
  int all = start < 0 ? mcv_widgetCount : 0;
  for (int i = 0; i < mcv_widgetCount; ++i)
  {
    if (i >= all)
    {
      break;
    }
    mcvAddWidget(i, x, transparency, weightSum, colourSum);
  }
)GLSL";
  if (bricks)
  {
    code += R"GLSL(
  int listed = start < 0 ? 0 : count;
  for (int j = 0; j < listed; ++j)
  {
    mcvAddWidget(int(mcvTableEntry(start + j).x), x, transparency, weightSum, colourSum);
  }
)GLSL";
  }
  code += R"GLSL(
  // Every weight underflowed (e < -87 for all widgets): the opacity is 0 as well.
  if (weightSum <= 0.0)
  {
    return vec4(0.0);
  }
  return vec4(colourSum / weightSum, clamp((1.0 - transparency) * texel.w, 0.0, 1.0));
}
)GLSL";
  return code;
}

std::string RayStart(bool jitter, bool bricks, bool table)
{
  std::string code = "//VTK::Shading::Init\n";
  if (table)
  {
    code += "  if (!mcvTableBound()) { discard; }\n";
  }
  if (bricks)
  {
    // A table not bound where the sampler reads (the mapper binds it and checks the
    // sampler after the first frame of a new shader): draw nothing rather than garbage.
    code += "  if (mcvTableEntry(0).x != MCV_CHECK) { discard; }\n";
  }
  if (jitter)
  {
    // Interleaved gradient noise (Jimenez 2014): a fixed per-pixel offset in [0, 1) with
    // no visible structure, and the same picture at every render (tests compare pixels).
    code += "  g_dataPos += g_dirStep * fract(52.9829189 * fract(dot(gl_FragCoord.xy,"
            " vec2(0.06711056, 0.00583715))));\n";
  }
  return code;
}

std::string SampleAndBlend(bool maximumIntensity, bool bricks)
{
  std::string code = R"GLSL(
    int mcvStart = -1;
    int mcvCount = mcv_widgetCount;
)GLSL";
  if (bricks)
  {
    // The sample's brick: its widget list, or, when no widget reaches it, a jump over its
    // remaining samples (whole steps, so the samples after it are today's).
    code += R"GLSL(
    if (!g_skip)
    {
      vec3 mcvVoxel = g_dataPos * mcv_volumeSize - 0.5;
      ivec3 mcvBrick = clamp(ivec3(floor(mcvVoxel / MCV_BRICK)), ivec3(0), ivec3(mcv_brickGrid) - 1);
      vec2 mcvList = mcvTableEntry(1 + mcvBrick.x + int(mcv_brickGrid.x) *
        (mcvBrick.y + int(mcv_brickGrid.y) * mcvBrick.z));
      mcvStart = int(mcvList.x);
      mcvCount = int(mcvList.y);
      if (mcvCount == 0)
      {
        vec3 mcvStep = g_dirStep * mcv_volumeSize;
        vec3 mcvFace = vec3(mcvBrick) * MCV_BRICK + MCV_BRICK * step(0.0, mcvStep);
        vec3 mcvExit = vec3(1.0e30);
        for (int a = 0; a < 3; ++a)
        {
          if (mcvStep[a] != 0.0)
          {
            mcvExit[a] = (mcvFace[a] - mcvVoxel[a]) / mcvStep[a];
          }
        }
        float mcvSkip = max(ceil(min(min(mcvExit.x, mcvExit.y), mcvExit.z)) - 1.0, 0.0);
        g_dataPos += g_dirStep * mcvSkip;
        g_currentT += mcvSkip;
      }
    }
)GLSL";
  }
  code += R"GLSL(
    if (!g_skip && mcvCount > 0)
    {
      vec4 mcvSample = mcvClassify(texture3D(in_volume[0], g_dataPos), mcvStart, mcvCount);
)GLSL";
  if (maximumIntensity)
  {
    code += R"GLSL(
      if (mcvSample.a > g_fragColor.a)
      {
        g_fragColor = vec4(mcvSample.rgb * mcvSample.a, mcvSample.a);
      }
    }
)GLSL";
  }
  else
  {
    code += R"GLSL(
      if (mcvSample.a > 0.0)
      {
        mcvSample.a = 1.0 - pow(1.0 - min(mcvSample.a, 1.0), in_sampleDistance / mcv_unitDistance);
        mcvSample.rgb *= mcvSample.a;
        g_fragColor = (1.0 - g_fragColor.a) * mcvSample + g_fragColor;
      }
    }
)GLSL";
  }
  return code;
}

} // namespace shader
} // namespace mcv
