#include "UMAPEmbedding.h"

#include "FeatureKnn.h"
#include "SeededRandom.h"
#include "UMAPGraph.h"
#include "UMAPLayout.h"
#include "UMAPLayoutDevice.h"
#include "UMAPSpectral.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace mcv
{

namespace
{
// Uniform double in [0, 1) from the top 53 bits.
double uniform01(std::uint64_t& state)
{
  return static_cast<double>(splitmix64(state) >> 11) * 0x1.0p-53;
}

// umap-learn's start: the spectral layout scaled to max |y| = 10 plus N(0, 1e-4) noise (Box-
// Muller), or uniform in [-10, 10]; then every axis mapped to [0, 10].
void scaleStart(RowMatrixF& Y, bool spectral, std::uint64_t seed)
{
  std::uint64_t state = mix64(seed ^ 0xA5A5A5A5DEADBEEFull);
  if (spectral)
  {
    const float maxAbs = Y.cwiseAbs().maxCoeff();
    Y *= maxAbs > 0 ? 10.f / maxAbs : 1.f;
    for (Eigen::Index i = 0; i < Y.size(); ++i)
    {
      const double u1 = 1.0 - uniform01(state), u2 = uniform01(state);
      Y.data()[i] += static_cast<float>(1e-4 * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
    }
  }
  else
  {
    for (Eigen::Index i = 0; i < Y.size(); ++i)
    {
      Y.data()[i] = static_cast<float>(-10.0 + 20.0 * uniform01(state));
    }
  }
  for (Eigen::Index c = 0; c < Y.cols(); ++c)
  {
    const float lo = Y.col(c).minCoeff(), range = Y.col(c).maxCoeff() - lo;
    if (range > 0)
    {
      Y.col(c) = (Y.col(c).array() - lo) * (10.f / range);
    }
  }
}
} // namespace

Embedding fitUMAP(const RowMatrixF& X, const UMAPOptions& o)
{
  Embedding e;
  const std::size_t n = static_cast<std::size_t>(X.rows());
  const int d = o.outputDimension;
  const int K = o.numberOfNeighbors;
  auto report = [&](const char* stage, double f) { reportStage(o.progress, stage, f); };
  if (d != 2 && d != 3)
  {
    e.error = "UMAP: the output dimension must be 2 or 3 (got " + std::to_string(d) + ").";
    return e;
  }
  e.error = neighboursError("UMAP", K, n);
  if (!e.error.empty())
  {
    return e;
  }
  if (n < static_cast<std::size_t>(d) + 2)
  {
    e.error = "UMAP: at least " + std::to_string(d + 2) + " reference points are needed.";
    return e;
  }
  if (!(o.minimumDistance >= 0.0 && o.minimumDistance <= 1.0))
  {
    e.error = "UMAP: MinimumDistance must be in [0, 1] (the spread), got " + std::to_string(o.minimumDistance) + ".";
    return e;
  }
  if (o.numberOfEpochs < 0)
  {
    e.error = "UMAP: NumberOfEpochs must be 0 (automatic) or positive, got " + std::to_string(o.numberOfEpochs) + ".";
    return e;
  }
  if (!X.allFinite())
  {
    e.error = "UMAP: the feature vectors contain NaN or Inf.";
    return e;
  }

  report("UMAP: neighbour graph", 0.0);
  const KnnGraph knn = buildReferenceGraph(X.data(), n, static_cast<int>(X.cols()), K, &e.referenceRadius);
  report("UMAP: fuzzy simplicial set", 0.1);
  FuzzyGraph graph = fuzzySimplicialSet(knn);
  const int epochs = o.numberOfEpochs > 0 ? o.numberOfEpochs : defaultEpochs(n);
  const float wMax = *std::max_element(graph.weight.begin(), graph.weight.end());
  // umap-learn: below 10 epochs the threshold of the default number is used.
  dropWeakEdges(graph, wMax / static_cast<float>(epochs > 10 ? epochs : defaultEpochs(n)));

  report("UMAP: spectral initialisation", 0.15);
  std::vector<std::uint32_t> label;
  const std::size_t components = connectedComponents(graph, label);
  RowMatrixF Y(static_cast<Eigen::Index>(n), d);
  bool spectral = false;
  if (components > 1)
  {
    e.warnings.push_back("UMAP: the fuzzy neighbour graph (K = " + std::to_string(K) + ") has " +
      std::to_string(components) + " connected components; the layout starts from random positions instead of "
      "the spectral initialisation. A larger NumberOfNeighbors may join them.");
  }
  else
  {
    SpectralLayout s = spectralLayout(graph, d);
    if (s.error.empty())
    {
      Y = std::move(s.coordinates);
      e.eigenvalues = std::move(s.eigenvalues);
      spectral = true;
    }
    else
    {
      e.warnings.push_back("UMAP: spectral initialisation failed (" + s.error +
        "); the layout starts from random positions.");
    }
  }
  scaleStart(Y, spectral, o.seed);

  const CurveParameters curve = fitCurveParameters(o.minimumDistance);
  if (!curve.converged)
  {
    e.warnings.push_back("UMAP: the fit of the curve parameters a, b to MinimumDistance did not converge.");
  }
  LayoutOptions lo;
  lo.epochs = epochs;
  lo.a = curve.a;
  lo.b = curve.b;
  lo.seed = o.seed;
  lo.progress = [&](const char* stage, double f) { report(stage, 0.2 + 0.8 * f); };
  report("UMAP: layout", 0.2);
  std::string deviceWarning;
  const Device device = o.device == Device::CPU ? Device::CPU : resolveDevice(o.device, &deviceWarning);
  if (!deviceWarning.empty())
  {
    e.warnings.push_back(deviceWarning);
  }
  optimizeLayoutOn(device, graph, lo, Y, e.warnings, o.gpuLayoutRounds);

  Eigen::MatrixXd axes = Y.cast<double>();
  toPrincipalAxes(axes);
  e.coordinates = axes.cast<float>();
  report("UMAP: done", 1.0);
  return e;
}

} // namespace mcv
