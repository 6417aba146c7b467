// The Gaussian widgets' palette and opacity formula, defined once for every place that
// evaluates them: the C++ core (GaussianTransferFunction.cpp, WidgetSeeding.cpp), the CUDA
// kernel (cuda/GaussianTFCuda.cu, through GaussianTransferFunction.h), the volume shader
// (Representations/mcvGaussianTFShader.cxx pastes the GLSL macros made below from the same
// macros), and the properties panel's editor. The Python helpers keep a copy for the
// client; Testing/Python/test_widget_formula.py checks it against this one.
//
// A widget i at mu_i with sigma_i and peak opacity a_i lets a sample at x through by
//   1 - alpha_i(x),  alpha_i(x) = a_i exp(-|x - mu_i|^2 / (2 sigma_i^2)),
// and the sample's opacity is 1 - prod_i (1 - alpha_i(x)). Evaluated in logs:
//   e_i = ln a_i - k_i |x - mu_i|^2 with k_i = 1 / (2 sigma_i^2), alpha_i = exp(e_i).
// Header-only and free of CUDA types, so that C++, CUDA and the Qt plugin include it alike.
#pragma once

#if defined(__CUDACC__)
#define MCV_HOST_DEVICE __host__ __device__
#else
#define MCV_HOST_DEVICE
#endif

// The formula as macros, so that the GLSL text is made from the same characters
// (mcv::widgetFormulaGLSL). Float literals carry the f suffix: float arithmetic in C++
// and CUDA, valid GLSL (1.30 and later).
#define MCV_WIDGET_LOG_WEIGHT(logA, k, d2) ((logA) - (d2) * (k))
#define MCV_WIDGET_TRANSMIT(transmit, weight, scale) ((transmit) * (1.0f - (weight) * (scale)))
#define MCV_WIDGET_STRINGIFY_(...) #__VA_ARGS__
#define MCV_WIDGET_STRINGIFY(...) MCV_WIDGET_STRINGIFY_(__VA_ARGS__)

namespace mcv
{

// ColorBrewer Set1 (Cynthia Brewer, colorbrewer2.org) without its grey, in its own order:
// red, blue, green, purple, orange, yellow, brown, pink (bytes; divide by 255).
constexpr int kWidgetPaletteSize = 8;
constexpr unsigned char kWidgetPalette[kWidgetPaletteSize][3] = { { 0xE4, 0x1A, 0x1C }, { 0x37, 0x7E, 0xB8 },
  { 0x4D, 0xAF, 0x4A }, { 0x98, 0x4E, 0xA3 }, { 0xFF, 0x7F, 0x00 }, { 0xFF, 0xFF, 0x33 }, { 0xA6, 0x56, 0x28 },
  { 0xF7, 0x81, 0xBF } };

// e_i = ln a_i - k_i d2: widget i's log-weight at squared distance d2. On the device each
// operation is rounded on its own (the _rn intrinsics are never fused into an FMA), as the
// CPU computes it (its files are built with -ffp-contract=off): the same bits on both.
MCV_HOST_DEVICE inline float widgetLogWeight(float logA, float k, float d2)
{
#if defined(__CUDA_ARCH__)
  return __fsub_rn(logA, __fmul_rn(d2, k));
#else
  return MCV_WIDGET_LOG_WEIGHT(logA, k, d2);
#endif
}

// The light left after one more widget: transmit (1 - alpha_i), alpha_i = weight x scale
// (exp(e_i - m) x exp(m) where m is the largest e_i, so that no weight underflows alone).
MCV_HOST_DEVICE inline float widgetTransmit(float transmit, float weight, float scale)
{
  return MCV_WIDGET_TRANSMIT(transmit, weight, scale);
}

// GLSL definitions of the same formula: mcvWidgetLogWeight(logA, k, d2) and
// mcvWidgetTransmit(transmit, weight, scale), as preprocessor macros of the shader.
inline const char* widgetFormulaGLSL()
{
  return "\n#define mcvWidgetLogWeight(logA, k, d2) " MCV_WIDGET_STRINGIFY(MCV_WIDGET_LOG_WEIGHT(logA, k, d2))
         "\n#define mcvWidgetTransmit(transmit, weight, scale) " MCV_WIDGET_STRINGIFY(
           MCV_WIDGET_TRANSMIT(transmit, weight, scale)) "\n";
}

} // namespace mcv
