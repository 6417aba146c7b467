// k-means by hand: the clustering is a few dozen lines on a few thousand 2D/3D points, and
// the C++ libraries that have it (mlpack, OpenCV) would be heavy new dependencies for that.
#include "WidgetSeeding.h"

#include "SeededRandom.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace mcv
{

int widgetPaletteSize()
{
  return kWidgetPaletteSize;
}

void widgetColor(int index, double rgb[3])
{
  const int i = ((index % (2 * kWidgetPaletteSize)) + 2 * kWidgetPaletteSize) % (2 * kWidgetPaletteSize);
  const double shade = i < kWidgetPaletteSize ? 1.0 : 0.6;
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = shade * kWidgetPalette[i % kWidgetPaletteSize][c] / 255.0;
  }
}

namespace
{

using Points = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

double uniform01(std::uint64_t& state)
{
  return static_cast<double>(uniformIndex(state, std::uint64_t(1) << 53)) / 9007199254740992.0;
}

// k-means++: each new centre drawn with probability proportional to the squared distance
// to the nearest centre so far.
Points kmeansPlusPlus(const Points& X, int k, std::uint64_t seed)
{
  std::uint64_t state = seed * 0x9E3779B97F4A7C15ull + 1;
  const Eigen::Index n = X.rows();
  Points centres(k, X.cols());
  centres.row(0) = X.row(static_cast<Eigen::Index>(uniformIndex(state, static_cast<std::uint64_t>(n))));
  Eigen::VectorXd nearest = (X.rowwise() - centres.row(0)).rowwise().squaredNorm();
  for (int c = 1; c < k; ++c)
  {
    const double total = nearest.sum();
    Eigen::Index pick = 0;
    if (total > 0)
    {
      double target = uniform01(state) * total;
      for (pick = 0; pick < n - 1; ++pick)
      {
        target -= nearest[pick];
        if (target < 0)
        {
          break;
        }
      }
    }
    centres.row(c) = X.row(pick);
    nearest = nearest.cwiseMin((X.rowwise() - centres.row(c)).rowwise().squaredNorm());
  }
  return centres;
}

// sigma of an isotropic Gaussian with the cluster's RMS spread; a cluster of identical
// points gets a tenth of the domain's (a usable widget rather than a zero-width one).
double clusterSigma(double squaredSpread, std::size_t m, int dims, double domainSigma)
{
  const double sigma = m > 0 ? std::sqrt(squaredSpread / (static_cast<double>(m) * dims)) : 0.0;
  if (sigma > 0)
  {
    return sigma;
  }
  return domainSigma > 0 ? 0.1 * domainSigma : 1.0;
}

// Peak opacity of the largest of several seeded widgets, as a fraction of the others'
// (WidgetSeeding.h says why).
constexpr double kVeilOpacity = 0.05;

// Distance from centre c to the nearest other centre (0 when there is none).
double nearestOtherCentre(const Points& centres, int c)
{
  double nearest = 0;
  for (Eigen::Index o = 0; o < centres.rows(); ++o)
  {
    if (o != c)
    {
      const double d = (centres.row(o) - centres.row(c)).norm();
      nearest = nearest > 0 ? std::min(nearest, d) : d;
    }
  }
  return nearest;
}

} // namespace

WidgetSeeding seedGaussianWidgets(const CoordinateView& points, const WidgetSeedingOptions& options)
{
  WidgetSeeding out;
  const int dims = points.components;
  if (dims != 2 && dims != 3)
  {
    out.error = "Widget seeding needs 2- or 3-component coordinates, not " + std::to_string(dims) + ".";
    return out;
  }
  if (options.count < 1)
  {
    out.error = "Widget seeding needs a widget count >= 1.";
    return out;
  }
  // Finite points, and the number of distinct ones (k cannot exceed it).
  std::vector<Eigen::Index> finite;
  for (std::size_t i = 0; i < points.count; ++i)
  {
    const float* p = points.data + i * dims;
    if (std::all_of(p, p + dims, [](float v) { return std::isfinite(v); }))
    {
      finite.push_back(static_cast<Eigen::Index>(i));
    }
  }
  Points X(static_cast<Eigen::Index>(finite.size()), dims);
  for (Eigen::Index r = 0; r < X.rows(); ++r)
  {
    for (int c = 0; c < dims; ++c)
    {
      X(r, c) = points.data[finite[static_cast<std::size_t>(r)] * dims + c];
    }
  }
  std::vector<std::vector<double>> rows(static_cast<std::size_t>(X.rows()));
  for (Eigen::Index r = 0; r < X.rows(); ++r)
  {
    rows[static_cast<std::size_t>(r)].assign(X.row(r).data(), X.row(r).data() + dims);
  }
  std::sort(rows.begin(), rows.end());
  const auto distinct = static_cast<int>(std::unique(rows.begin(), rows.end()) - rows.begin());
  if (distinct == 0)
  {
    out.error = "Widget seeding: no point has finite coordinates.";
    return out;
  }
  const int wanted = options.count + (options.skipLargest ? 1 : 0);
  if (options.skipLargest && distinct < 2)
  {
    out.error = "Widget seeding: one distinct point, nothing left once the largest cluster "
                "(the background) is skipped.";
    return out;
  }
  const int k = std::min(wanted, distinct);
  const int first = options.skipLargest ? 1 : 0; // clusters (by size) that become widgets

  Points centres = kmeansPlusPlus(X, k, options.seed);
  std::vector<int> label(static_cast<std::size_t>(X.rows()), -1);
  for (out.iterations = 0; out.iterations < std::max(1, options.maxIterations); ++out.iterations)
  {
    bool changed = false;
    for (Eigen::Index r = 0; r < X.rows(); ++r)
    {
      Eigen::Index best;
      (centres.rowwise() - X.row(r)).rowwise().squaredNorm().minCoeff(&best);
      changed = changed || label[static_cast<std::size_t>(r)] != static_cast<int>(best);
      label[static_cast<std::size_t>(r)] = static_cast<int>(best);
    }
    if (!changed)
    {
      break;
    }
    Points sums = Points::Zero(k, dims);
    Eigen::VectorXd counts = Eigen::VectorXd::Zero(k);
    for (Eigen::Index r = 0; r < X.rows(); ++r)
    {
      sums.row(label[static_cast<std::size_t>(r)]) += X.row(r);
      counts[label[static_cast<std::size_t>(r)]] += 1;
    }
    for (int c = 0; c < k; ++c)
    {
      if (counts[c] > 0) // an emptied cluster keeps its centre
      {
        centres.row(c) = sums.row(c) / counts[c];
      }
    }
  }

  // Spread and points per cluster, and its size: the voxels its points stand for (their
  // weights). Then order by size (stable: equal sizes keep k-means' order, so the order is
  // deterministic).
  std::vector<double> spread(static_cast<std::size_t>(k), 0.0);
  std::vector<std::size_t> count(static_cast<std::size_t>(k), 0);
  std::vector<double> size(static_cast<std::size_t>(k), 0.0);
  for (Eigen::Index r = 0; r < X.rows(); ++r)
  {
    const int c = label[static_cast<std::size_t>(r)];
    spread[static_cast<std::size_t>(c)] += (X.row(r) - centres.row(c)).squaredNorm();
    ++count[static_cast<std::size_t>(c)];
    size[static_cast<std::size_t>(c)] += options.weights ? options.weights[finite[static_cast<std::size_t>(r)]] : 1.0;
  }
  // The domain's own spread: sigma for a cluster of one point (or identical points).
  const double domainSigma =
    std::sqrt((X.rowwise() - X.colwise().mean()).rowwise().squaredNorm().mean() / dims);
  std::vector<int> order(static_cast<std::size_t>(k));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&size](int a, int b) { return size[a] > size[b]; });

  // Shares count the voxels of the widgets' clusters, not the skipped background's.
  const double totalSize = std::accumulate(size.begin(), size.end(), 0.0) -
    (first > 0 ? size[static_cast<std::size_t>(order[0])] : 0.0);
  std::vector<int> rank(static_cast<std::size_t>(k), -2);
  if (first > 0)
  {
    out.skippedSize = static_cast<std::size_t>(std::llround(size[static_cast<std::size_t>(order[0])]));
  }
  for (int i = first; i < k; ++i)
  {
    const int c = order[static_cast<std::size_t>(i)];
    rank[static_cast<std::size_t>(c)] = i - first;
    GaussianWidget w;
    for (int d = 0; d < dims; ++d)
    {
      w.center[d] = centres(c, d);
    }
    w.sigma = clusterSigma(spread[static_cast<std::size_t>(c)], count[static_cast<std::size_t>(c)], dims, domainSigma);
    // Little overlap: at most a quarter of the way to the nearest other centre (the
    // skipped background's included, which then keeps a weight below exp(-8)).
    const double nearest = nearestOtherCentre(centres, c);
    if (nearest > 0)
    {
      w.sigma = std::min(w.sigma, 0.25 * nearest);
    }
    widgetColor(i - first, w.color);
    const double peak = std::min(1.0, std::max(0.0, options.opacity));
    const double share = totalSize > 0 ? size[static_cast<std::size_t>(c)] / totalSize : 0.0;
    // Mean Gaussian weight of the widget over the points of its cluster (weighted).
    double weightSum = 0, weightedGauss = 0;
    for (Eigen::Index r = 0; r < X.rows(); ++r)
    {
      if (label[static_cast<std::size_t>(r)] == c)
      {
        const double wr = options.weights ? options.weights[finite[static_cast<std::size_t>(r)]] : 1.0;
        const double d2 = (X.row(r) - centres.row(c)).squaredNorm();
        weightSum += wr;
        weightedGauss += wr * std::exp(-d2 / (2 * w.sigma * w.sigma));
      }
    }
    const double meanWeight = weightSum > 0 ? weightedGauss / weightSum : 1.0;
    if (options.rayLength > 0)
    {
      // WidgetSeeding.h, "Opacity from the voxels a widget selects".
      const double crossed = share * options.rayLength;
      const double t = std::min(1.0, std::max(1e-6, options.transmission));
      const double perVoxel = crossed > 1 ? 1.0 - std::pow(t, 1.0 / crossed) : 1.0 - t;
      w.opacity = std::min(peak, perVoxel / std::max(meanWeight, 1e-6));
      out.hidden.push_back(share > options.hideShare);
    }
    else
    {
      // The largest of several widgets is the class that holds the others (a head's scalp
      // and skull around the brain once the air is masked): a faint veil.
      const bool veil = i == first && k - first > 1;
      w.opacity = peak * (veil ? kVeilOpacity : 1.0);
      out.hidden.push_back(false);
    }
    out.shares.push_back(share);
    out.meanWeights.push_back(meanWeight);
    out.widgets.push_back(w);
    out.clusterSizes.push_back(static_cast<std::size_t>(std::llround(size[static_cast<std::size_t>(c)])));
  }
  out.labels.assign(points.count, -1);
  for (std::size_t r = 0; r < finite.size(); ++r)
  {
    out.labels[static_cast<std::size_t>(finite[r])] = rank[static_cast<std::size_t>(label[r])];
  }
  return out;
}

} // namespace mcv
