// Every reduction method in one table: its name, how it is fitted on the reference sample,
// and what the rest of the reduction asks of it. A fifth method is a row here, its own fit
// file (as UMAPEmbedding.cpp), its entry in the Method list of DimensionReduction.xml (and
// the enum of vtkDimensionReduction.h, which must keep the table's order) and a test.
#pragma once

#include "DimensionReduction.h" // ReductionMethod, ReductionOptions
#include "Embedding.h"
#include "PCAEmbedding.h" // PCAModel

#include <string>
#include <vector>

namespace mcv
{

struct ReductionMethodInfo
{
  ReductionMethod method;
  const char* name;
  // Fitted on a k-nearest-neighbour graph of the sample: NumberOfNeighbors (fewer than
  // the sample) and NumberOfLandmarks apply.
  bool neighbourGraph;
  // A linear map: every voxel is projected (pca), not placed by its 3 nearest references.
  bool projects;
  // The eigenvalues are variances: the spectrum shows each one's share, and
  // varianceRetained means what it says. (LLE and UMAP return the smallest eigenvalues of
  // a graph operator.)
  bool varianceSpectrum;
  // The fit on the reference rows (M x D). `pca` receives the linear map of a projecting
  // method.
  Embedding (*fit)(const RowMatrixF& reference, const ReductionOptions& options, const StageProgress& progress,
    PCAModel* pca);
};

// In the order of ReductionMethod's values.
const std::vector<ReductionMethodInfo>& reductionMethods();
// Null when `method` is no method of the table.
const ReductionMethodInfo* findReductionMethod(ReductionMethod method);
const ReductionMethodInfo* findReductionMethod(const std::string& name);

} // namespace mcv
