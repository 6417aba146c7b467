#include "mcvGaussianTFShader.h"

#include "GaussianWidgetFormula.h"

namespace mcv
{
namespace shader
{

std::string ClassifyDeclaration()
{
  return mcv::widgetFormulaGLSL() + std::string(R"GLSL(
// Multichannel Explorer: Gaussian widgets evaluated per sample.
vec4 mcvClassify(vec4 texel)
{
  if (texel.w <= 0.0 || mcv_widgetCount <= 0)
  {
    return vec4(0.0);
  }
  vec3 x = mcv_coordinateMin + mcv_coordinateExtent * (texel.xyz / texel.w);
  float transparency = 1.0;
  float maxLogWeight = -3.0e38;
  float weightSum = 0.0;
  vec3 colourSum = vec3(0.0);
  for (int i = 0; i < mcv_widgetCount; ++i)
  {
    vec3 d = x - mcv_widgetCentreK[i].xyz;
    float e = mcvWidgetLogWeight(mcv_widgetColourLogA[i].w, mcv_widgetCentreK[i].w, dot(d, d));
    transparency = mcvWidgetTransmit(transparency, exp(e), 1.0);
    if (e > maxLogWeight)
    {
      float rescale = exp(maxLogWeight - e);
      weightSum = weightSum * rescale + 1.0;
      colourSum = colourSum * rescale + mcv_widgetColourLogA[i].rgb;
      maxLogWeight = e;
    }
    else
    {
      float w = exp(e - maxLogWeight);
      weightSum += w;
      colourSum += w * mcv_widgetColourLogA[i].rgb;
    }
  }
  return vec4(colourSum / weightSum, clamp((1.0 - transparency) * texel.w, 0.0, 1.0));
}
)GLSL");
}

std::string RayStart(bool jitter)
{
  std::string code = "//VTK::Shading::Init\n";
  if (jitter)
  {
    // Interleaved gradient noise (Jimenez 2014): a fixed per-pixel offset in [0, 1) with
    // no visible structure, and the same picture at every render (tests compare pixels).
    code += "  g_dataPos += g_dirStep * fract(52.9829189 * fract(dot(gl_FragCoord.xy,"
            " vec2(0.06711056, 0.00583715))));\n";
  }
  return code;
}

std::string SampleAndBlend(bool maximumIntensity)
{
  std::string code = R"GLSL(
    if (!g_skip)
    {
      vec4 mcvSample = mcvClassify(texture3D(in_volume[0], g_dataPos));
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
