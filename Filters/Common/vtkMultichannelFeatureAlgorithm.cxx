#include "vtkMultichannelFeatureAlgorithm.h"

#include "FeatureVectors.h"
#include "ImageGrid.h"
#include "mcvPrintMembers.h"
#include "vtkImageData.h"

#include <cmath>

vtkMultichannelFeatureAlgorithm::vtkMultichannelFeatureAlgorithm() = default;
vtkMultichannelFeatureAlgorithm::~vtkMultichannelFeatureAlgorithm() = default;

void vtkMultichannelFeatureAlgorithm::SetFeatureOptions(int preset, mcv::FeatureOptions& options) const
{
  options.preset = static_cast<mcv::FeaturePreset>(preset);
  options.custom.intensity = this->Intensity;
  options.custom.gradient = this->Gradient;
  options.custom.gradientMagnitude = this->GradientMagnitude;
  options.custom.laplacian = this->Laplacian;
  options.custom.localMean = this->LocalMean;
  options.custom.localVariance = this->LocalVariance;
  options.normalization = static_cast<mcv::FeatureNormalization>(this->Normalization);
}

void vtkMultichannelFeatureAlgorithm::SetGridSpacing(vtkImageData* image, mcv::ImageGrid& grid)
{
  double spacing[3];
  image->GetSpacing(spacing);
  for (int a = 0; a < 3; ++a)
  {
    grid.spacing[a] = std::abs(spacing[a]);
  }
}

bool vtkMultichannelFeatureAlgorithm::CheckFeatureCount(int featureCount)
{
  if (featureCount > 0)
  {
    return true;
  }
  vtkErrorMacro("No feature selected: FeatureSet is Custom and every feature toggle "
                "(Intensity, Gradient, GradientMagnitude, Laplacian, LocalMean, "
                "LocalVariance) is off.");
  return false;
}

void vtkMultichannelFeatureAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  mcvPrintMembersMacro(os, indent, this->Intensity, this->Gradient, this->GradientMagnitude,
    this->Laplacian, this->LocalMean, this->LocalVariance, this->Normalization,
    this->MaskBackground, this->BackgroundThreshold);
}
