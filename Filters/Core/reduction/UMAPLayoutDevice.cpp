#include "UMAPLayoutDevice.h"

#include "UMAPGraph.h"

#ifdef MCV_HAS_CUDA
#include "cuda/UMAPLayoutCuda.h"
#endif

namespace mcv
{

bool optimizeLayoutOnGpu(const FuzzyGraph& graph, const LayoutOptions& options, RowMatrixF& Y, std::string* error,
  int gpuRounds)
{
#ifdef MCV_HAS_CUDA
  // The CSR rows as directed edges: row i's entries all have head i.
  std::vector<std::uint32_t> head(graph.edgeCount());
  for (std::size_t i = 0; i < graph.n; ++i)
  {
    std::fill(head.begin() + static_cast<std::ptrdiff_t>(graph.start[i]),
      head.begin() + static_cast<std::ptrdiff_t>(graph.start[i + 1]), static_cast<std::uint32_t>(i));
  }
  cuda::LayoutProblem p;
  p.n = graph.n;
  p.dim = static_cast<int>(Y.cols());
  p.edges = graph.edgeCount();
  p.head = head.data();
  p.tail = graph.to.data();
  p.weight = graph.weight.data();
  p.epochs = options.epochs;
  p.a = options.a;
  p.b = options.b;
  p.gamma = options.gamma;
  p.initialAlpha = options.initialAlpha;
  p.negativeSampleRate = options.negativeSampleRate;
  p.seed = options.seed;
  if (gpuRounds > 0)
  {
    p.rounds = gpuRounds;
  }
  std::function<void(double)> progress;
  if (options.progress)
  {
    progress = [&](double f) { options.progress("UMAP: layout (GPU)", f); };
  }
  RowMatrixF out = Y; // Y stays the start if the GPU fails midway
  if (!cuda::optimizeLayout(p, out.data(), progress, nullptr, error))
  {
    return false;
  }
  Y = std::move(out);
  return true;
#else
  (void)graph;
  (void)options;
  (void)Y;
  (void)gpuRounds;
  if (error)
  {
    *error = "this build has no CUDA";
  }
  return false;
#endif
}

Device optimizeLayoutOn(Device device, const FuzzyGraph& graph, const LayoutOptions& options, RowMatrixF& Y,
  std::vector<std::string>& warnings, int gpuRounds)
{
  if (device == Device::GPU)
  {
    std::string error;
    if (optimizeLayoutOnGpu(graph, options, Y, &error, gpuRounds))
    {
      return Device::GPU;
    }
    warnings.push_back("The GPU UMAP layout failed (" + error + "); it ran on the CPU.");
  }
  optimizeLayout(graph, options, Y);
  return Device::CPU;
}

} // namespace mcv
