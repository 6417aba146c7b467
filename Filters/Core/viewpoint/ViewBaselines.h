// Baseline viewpoint methods kept for comparison with the Harris/PCA method
// (dissertation section 7.5): area maximising and viewpoint (opacity) entropy.
#pragma once

#include "ImageGrid.h"
#include "ViewFromPoints.h"

#include <functional>
#include <vector>

namespace mcv
{

// Area maximising (eq. 7.10-7.11) on the tight world-space bounding box of voxels with
// opacity > threshold: u = (hd, dw, wh) / K. Worst = the axis of the smallest face.
// Invalid (with a message) when no voxel exceeds the threshold.
ViewDirections areaMaximizingView(
  const float* opacity, const ImageGrid& grid, float threshold = 0.0f);

struct EntropyOptions
{
  int samples = 400;    // view directions on a Fibonacci sphere
  int imageSize = 128;  // square image, pixels per side
};

// Orthographic front-to-back ray casting of the opacity volume along `direction`:
// each pixel holds the accumulated opacity. Image covers the volume's bounding sphere.
std::vector<float> renderOpacityImage(
  const float* opacity, const ImageGrid& grid, const Vec3& direction, int imageSize);

// Shannon entropy (bits) of an image seen as a distribution p_i = I_i / sum I.
double imageEntropy(const float* pixels, std::size_t count);

// Viewpoint entropy (Ji & Shen 2006, opacity only): the sample direction whose opacity
// image has the highest entropy is `best`, the lowest `worst`. `progress` gets [0,1].
ViewDirections viewpointEntropyView(const float* opacity, const ImageGrid& grid,
  const EntropyOptions& options, const std::function<void(double)>& progress = {});

} // namespace mcv
