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

// The settings every neighbour-graph method (Isomap, LLE, UMAP) takes from the reduction's
// options; each method adds its own.
template <class MethodOptions>
MethodOptions graphMethodOptions(const ReductionOptions& o, const StageProgress& progress)
{
  MethodOptions m;
  m.outputDimension = o.outputDimension;
  m.numberOfNeighbors = o.numberOfNeighbors;
  m.seed = o.randomSeed;
  m.progress = progress;
  return m;
}

Embedding fitIsomapMethod(const RowMatrixF& x, const ReductionOptions& o, const StageProgress& progress, PCAModel*)
{
  IsomapOptions io = graphMethodOptions<IsomapOptions>(o, progress);
  io.numberOfLandmarks = o.numberOfLandmarks;
  io.device = resolveDevice(o.device); // reduceDimension warns once if the GPU is missing
  return fitIsomap(x, io);
}

Embedding fitLLEMethod(const RowMatrixF& x, const ReductionOptions& o, const StageProgress& progress, PCAModel*)
{
  LLEOptions lo = graphMethodOptions<LLEOptions>(o, progress);
  lo.numberOfLandmarks = o.numberOfLandmarks;
  return fitLLE(x, lo);
}

Embedding fitUMAPMethod(const RowMatrixF& x, const ReductionOptions& o, const StageProgress& progress, PCAModel*)
{
  UMAPOptions uo = graphMethodOptions<UMAPOptions>(o, progress);
  uo.minimumDistance = o.minimumDistance;
  uo.numberOfEpochs = o.numberOfEpochs;
  uo.device = resolveDevice(o.device); // reduceDimension warns once if the GPU is missing
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
