#include "ReductionMethods.h"

#include "IsomapEmbedding.h"
#include "LLEEmbedding.h"
#include "UMAPEmbedding.h"

namespace mcv
{
namespace
{

Embedding fitPCAMethod(const RowMatrixF& x, const ReductionOptions& o, const StageProgress& progress, PCAModel* pca)
{
  progress("PCA", 0.0);
  return fitPCA(x.data(), static_cast<std::size_t>(x.rows()), static_cast<int>(x.cols()), {}, {}, o.outputDimension, pca);
}

Embedding fitIsomapMethod(const RowMatrixF& x, const ReductionOptions& o, const StageProgress& progress, PCAModel*)
{
  IsomapOptions io;
  io.outputDimension = o.outputDimension;
  io.numberOfNeighbors = o.numberOfNeighbors;
  io.numberOfLandmarks = o.numberOfLandmarks;
  io.seed = o.randomSeed;
  io.progress = progress;
  return fitIsomap(x, io);
}

Embedding fitLLEMethod(const RowMatrixF& x, const ReductionOptions& o, const StageProgress& progress, PCAModel*)
{
  LLEOptions lo;
  lo.outputDimension = o.outputDimension;
  lo.numberOfNeighbors = o.numberOfNeighbors;
  lo.numberOfLandmarks = o.numberOfLandmarks;
  lo.seed = o.randomSeed;
  lo.progress = progress;
  return fitLLE(x, lo);
}

Embedding fitUMAPMethod(const RowMatrixF& x, const ReductionOptions& o, const StageProgress& progress, PCAModel*)
{
  UMAPOptions uo;
  uo.outputDimension = o.outputDimension;
  uo.numberOfNeighbors = o.numberOfNeighbors;
  uo.minimumDistance = o.minimumDistance;
  uo.numberOfEpochs = o.numberOfEpochs;
  uo.seed = o.randomSeed;
  uo.device = resolveDevice(o.device); // reduceDimension warns once if the GPU is missing
  uo.progress = progress;
  return fitUMAP(x, uo);
}

} // namespace

const std::vector<ReductionMethodInfo>& reductionMethods()
{
  //                                    name      graph  projects variances fit
  static const std::vector<ReductionMethodInfo> table{
    { ReductionMethod::PCA, "PCA", false, true, true, fitPCAMethod },
    { ReductionMethod::Isomap, "Isomap", true, false, true, fitIsomapMethod },
    { ReductionMethod::LLE, "LLE", true, false, false, fitLLEMethod },
    { ReductionMethod::UMAP, "UMAP", true, false, false, fitUMAPMethod },
  };
  return table;
}

const ReductionMethodInfo* findReductionMethod(ReductionMethod method)
{
  for (const ReductionMethodInfo& m : reductionMethods())
  {
    if (m.method == method)
    {
      return &m;
    }
  }
  return nullptr;
}

const ReductionMethodInfo* findReductionMethod(const std::string& name)
{
  for (const ReductionMethodInfo& m : reductionMethods())
  {
    if (name == m.name)
    {
      return &m;
    }
  }
  return nullptr;
}

} // namespace mcv
