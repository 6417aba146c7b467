// What a fit of the dimension reduction produces, kept so that other volumes (time steps,
// subjects, samples) are placed in the same reduced domain without a new fit: the same
// tissue then gets the same coordinates, hence the same colours, everywhere.
//
// The reduction part lives here (VTK-free): the method, the feature columns it used, the
// reference sample's feature vectors and their embedding, what PCA projects with, and the
// spread of the references that decides when a voxel lies outside the model. The features
// part (channels by name, feature set, the normalisation's offsets and scales, spacing)
// and the file format are the VTK layer's (Filters/Reduction/mcvReductionModelFile.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mcv
{

enum class ReductionMethod;

// A voxel is out of the model when its distance to the nearest reference exceeds
// kOutOfModelRatio times the model's referenceRadius (ModelDistance > kOutOfModelRatio).
// The radius is the fit's own largest 3-NN distance among the references, the farthest a
// reference reaches for the neighbours it is placed by; the margin keeps the fit volume's
// own tails in (measured: docs/architecture.md, "Reduction models").
constexpr double kOutOfModelRatio = 1.5;

struct ReductionModel
{
  ReductionMethod method{};
  int outputDimension = 0;
  int featureColumns = 0;            // components of the rows the fit read
  std::vector<int> usedColumns;      // those that vary (D of them), in order
  std::size_t references = 0;        // M
  std::vector<float> referenceFeatures;    // M x D, row-major: the used columns
  std::vector<float> referenceCoordinates; // M x d, row-major: their embedding
  std::vector<double> pcaMean;       // PCA: D
  std::vector<double> pcaAxes;       // PCA: D x d, column-major (unit columns)
  double referenceRadius = 0.0;      // largest distance of a reference to its 3rd nearest other
  // What the fit reported, repeated wherever the model is applied.
  std::vector<double> eigenvalues;
  double varianceRetained = 0.0;
  double trustworthiness = 0.0;

  int usedCount() const { return static_cast<int>(usedColumns.size()); }
  // "" when the sizes agree and every value is finite; else what is wrong.
  std::string check() const;
};

// The name of a method ("PCA", "Isomap", "LLE", "UMAP"; "unknown" otherwise) and back
// (false for another name).
const char* reductionMethodName(ReductionMethod method);
bool reductionMethodFromName(const std::string& name, ReductionMethod& method);

} // namespace mcv
