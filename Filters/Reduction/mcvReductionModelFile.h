// A reduction model as a file (`.mcvmodel`): what DimensionReduction fitted, so that other
// volumes, time steps or sessions are placed in the same reduced domain without a new fit.
//
// Layout (all numbers little-endian):
//   bytes 0-7     the magic "MCVMODEL"
//   uint32        format version (kModelFormatVersion)
//   uint32        H, the length of the header
//   H bytes       the header: JSON (UTF-8), human-readable: the channels by name and order,
//                 the feature set, its normalisation and the fit volume's spacing, the method
//                 and its parameters, the sizes, and the list of binary blocks that follow
//   blocks        in the header's order ("blocks": name, type float32/float64/int32, count)
//   uint32        CRC-32 (zlib's) of every byte before it
// JSON for what a person or a script reads (Python's json, jq), raw little-endian blocks for
// the ~1 MB of reference vectors that JSON would triple and round. docs/architecture.md says
// why this format and not another.
#pragma once

#include "DimensionReduction.h" // mcv::ReductionModel, ReductionMethod
#include "FeatureVectors.h"     // mcv::FeatureSelection, FeatureNormalization, FeaturePreset

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mcv
{
namespace vtkhelpers
{

constexpr std::uint32_t kModelFormatVersion = 1;

// How the rows the model places are made from a volume: computed from these channels (by
// name, in this order) with this feature set and the fit volume's normalisation.
struct FeatureRecipe
{
  std::vector<std::string> channels;
  FeaturePreset preset = FeaturePreset::TwentyFourD;
  FeatureSelection selection; // the columns each channel contributes (the preset's or custom)
  FeatureNormalization normalization = FeatureNormalization::ZScore;
  std::vector<std::string> featureNames; // one per column
  std::vector<double> offset, scale;     // one per column: x -> (x - offset) * scale
  std::array<double, 3> spacing{ 1, 1, 1 }; // of the fit volume (gradients are per world unit)
  std::string lengthUnit;                 // of that spacing, when the reader knew it
  bool maskBackground = true;
  double backgroundThreshold = 0.0;
};

// The fit's parameters, recorded for the person reading the file (not needed to apply it).
struct FitRecord
{
  int numberOfNeighbors = 0, numberOfLandmarks = 0, numberOfEpochs = 0;
  double minimumDistance = 0.0;
  std::uint64_t referenceSampleSize = 0, randomSeed = 0, sampledVoxels = 0;
  std::array<int, 3> volumeDimensions{ 0, 0, 0 };
  std::string fittedOn; // e.g. "time step 2 of 3", "every time step"
};

struct ModelFile
{
  FeatureRecipe features;
  ReductionModel reduction;
  FitRecord fit;
};

// The file's bytes (never fails for a model that passes ReductionModel::check).
std::vector<char> encodeModel(const ModelFile& model);

// Parses bytes read from `where` (named in the messages); "" on success, else why not (a
// truncated or corrupt file, another format, a newer version, sizes that disagree, NaN).
// `model` is only written on success.
std::string decodeModel(const std::vector<char>& bytes, const std::string& where, ModelFile& model);

// The whole file, read; "" or why not (missing, unreadable).
std::string readFileBytes(const std::string& path, std::vector<char>& bytes);

// Writes `bytes` to `path` through a temporary file in the same folder renamed into place,
// so that no half-written model ever carries the name; "" or why not.
std::string writeFileAtomically(const std::string& path, const std::vector<char>& bytes);

} // namespace vtkhelpers
} // namespace mcv
