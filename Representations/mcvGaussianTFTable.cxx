#include "mcvGaussianTFTable.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mcv
{
namespace tftable
{
namespace
{

// Where a widget exceeds Cutoff: squared reach (ln a - ln Cutoff) / k; negative: nowhere.
double reachSquared(const mcv::detail::PackedGaussianWidget& w)
{
  return (static_cast<double>(w.logA) - std::log(Cutoff)) / static_cast<double>(w.k);
}

// True when the widget exceeds Cutoff somewhere in the box [minimum, minimum + extent].
bool reachesDomain(
  const mcv::detail::PackedGaussianWidget& w, const float minimum[3], const float extent[3])
{
  const double reach2 = reachSquared(w);
  if (!(reach2 > 0))
  {
    return false;
  }
  const float centre[3] = { w.cx, w.cy, w.cz };
  double d2 = 0;
  for (int c = 0; c < 3; ++c)
  {
    const double lo = minimum[c], hi = static_cast<double>(minimum[c]) + extent[c];
    const double d = centre[c] < lo ? lo - centre[c] : (centre[c] > hi ? centre[c] - hi : 0.0);
    d2 += d * d;
  }
  return d2 <= reach2;
}

// One widget's per-axis factors exp(-k (x_c(i) - mu_c)^2) over the nodes where it can
// exceed Cutoff ([first, last] per axis; first > last: nowhere), the peak opacity folded
// into z.
struct WidgetFactors
{
  std::vector<float> f[3];
  int first[3] = { 0, 0, 0 };
  int last[3] = { -1, -1, -1 };
  float colour[3] = { 0, 0, 0 };
};

WidgetFactors factorsOf(const mcv::detail::PackedGaussianWidget& w, const float minimum[3],
  const float extent[3], const int nodes[3])
{
  WidgetFactors result;
  result.colour[0] = w.r;
  result.colour[1] = w.g;
  result.colour[2] = w.b;
  const double reach2 = reachSquared(w);
  if (!(reach2 > 0))
  {
    return result;
  }
  const double reach = std::sqrt(reach2);
  const float centre[3] = { w.cx, w.cy, w.cz };
  const double peak = std::exp(static_cast<double>(w.logA));
  for (int c = 0; c < 3; ++c)
  {
    result.f[c].assign(static_cast<size_t>(nodes[c]), 0.0f);
    const double step = nodes[c] > 1 ? static_cast<double>(extent[c]) / (nodes[c] - 1) : 0.0;
    int first = nodes[c], last = -1;
    for (int i = 0; i < nodes[c]; ++i)
    {
      const double d = static_cast<double>(minimum[c]) + step * i - centre[c];
      if (std::abs(d) <= reach)
      {
        result.f[c][static_cast<size_t>(i)] =
          static_cast<float>(std::exp(-static_cast<double>(w.k) * d * d) * (c == 2 ? peak : 1.0));
        first = std::min(first, i);
        last = std::max(last, i);
      }
    }
    result.first[c] = first;
    result.last[c] = last;
  }
  return result;
}

std::uint16_t toUnorm16(float v)
{
  const float clamped = std::min(1.0f, std::max(0.0f, v));
  return static_cast<std::uint16_t>(std::lround(clamped * 65535.0f));
}

} // namespace

TableSize chooseTableSize(const std::vector<mcv::detail::PackedGaussianWidget>& widgets,
  const float minimum[3], const float extent[3])
{
  TableSize size;
  double narrowest = 0; // sigma of the narrowest widget that reaches the domain
  for (const auto& w : widgets)
  {
    if (reachesDomain(w, minimum, extent))
    {
      const double sigma = 1.0 / std::sqrt(2.0 * static_cast<double>(w.k));
      narrowest = narrowest > 0 ? std::min(narrowest, sigma) : sigma;
    }
  }
  for (int c = 0; c < 3; ++c)
  {
    if (!(extent[c] > 0))
    {
      size.nodes[c] = 1;
      continue;
    }
    if (!(narrowest > 0))
    {
      size.nodes[c] = 2; // no widget: a transparent table
      continue;
    }
    // (1 - 1e-6): a ratio that is a whole number up to float rounding stays that number.
    const double intervals =
      std::ceil(static_cast<double>(extent[c]) * CellsPerSigma / narrowest * (1.0 - 1.0e-6));
    if (intervals + 1 > MaximumNodes)
    {
      std::ostringstream why;
      why << "a widget of sigma " << narrowest << " needs " << intervals + 1
          << " table nodes on axis " << c << " (extent " << extent[c] << "), more than "
          << MaximumNodes;
      size = TableSize();
      size.reason = why.str();
      return size;
    }
    size.nodes[c] = std::max(2, static_cast<int>(intervals) + 1);
  }
  if (size.Count() > MaximumTableNodes)
  {
    std::ostringstream why;
    why << "a widget of sigma " << narrowest << " needs " << size.nodes[0] << " x "
        << size.nodes[1] << " x " << size.nodes[2] << " table nodes, more than "
        << MaximumTableNodes;
    size = TableSize();
    size.reason = why.str();
  }
  return size;
}

std::vector<std::uint16_t> bakeTable(const std::vector<mcv::detail::PackedGaussianWidget>& widgets,
  const float minimum[3], const float extent[3], const TableSize& size)
{
  const int nx = size.nodes[0], ny = size.nodes[1], nz = size.nodes[2];
  const size_t slice = static_cast<size_t>(nx) * static_cast<size_t>(ny);
  std::vector<std::uint16_t> texels(4 * slice * static_cast<size_t>(nz + 1), 0);
  std::vector<WidgetFactors> factors;
  for (const auto& w : widgets)
  {
    if (reachesDomain(w, minimum, extent))
    {
      factors.push_back(factorsOf(w, minimum, extent, size.nodes));
    }
  }
  const float cutoff = static_cast<float>(Cutoff);
  vtkSMPTools::For(0, nz, [&](int zBegin, int zEnd) {
    // Per slice: transparency prod (1 - alpha_i), weight sum, colour sums.
    std::vector<float> transparency(slice), weights(slice), red(slice), green(slice), blue(slice);
    for (int k = zBegin; k < zEnd; ++k)
    {
      std::fill(transparency.begin(), transparency.end(), 1.0f);
      std::fill(weights.begin(), weights.end(), 0.0f);
      std::fill(red.begin(), red.end(), 0.0f);
      std::fill(green.begin(), green.end(), 0.0f);
      std::fill(blue.begin(), blue.end(), 0.0f);
      for (const WidgetFactors& w : factors)
      {
        if (k < w.first[2] || k > w.last[2])
        {
          continue;
        }
        const float fz = w.f[2][static_cast<size_t>(k)];
        const float* fx = w.f[0].data();
        for (int j = w.first[1]; j <= w.last[1]; ++j)
        {
          const float fyz = w.f[1][static_cast<size_t>(j)] * fz;
          if (fyz < cutoff)
          {
            continue; // no node of the row exceeds the cutoff (fx <= 1)
          }
          const size_t row = static_cast<size_t>(j) * nx;
          for (int i = w.first[0]; i <= w.last[0]; ++i)
          {
            const float alpha = fyz * fx[i];
            transparency[row + i] *= 1.0f - alpha;
            weights[row + i] += alpha;
            red[row + i] += alpha * w.colour[0];
            green[row + i] += alpha * w.colour[1];
            blue[row + i] += alpha * w.colour[2];
          }
        }
      }
      std::uint16_t* out = texels.data() + 4 * slice * static_cast<size_t>(k);
      for (size_t n = 0; n < slice; ++n)
      {
        if (weights[n] > 0)
        {
          const float inverse = 1.0f / weights[n];
          out[4 * n + 0] = toUnorm16(red[n] * inverse);
          out[4 * n + 1] = toUnorm16(green[n] * inverse);
          out[4 * n + 2] = toUnorm16(blue[n] * inverse);
          out[4 * n + 3] = toUnorm16(1.0f - transparency[n]);
        }
      }
    }
  });
  std::uint16_t* check = texels.data() + 4 * slice * static_cast<size_t>(nz);
  for (size_t n = 0; n < slice; ++n)
  {
    std::copy(CheckTexel, CheckTexel + 4, check + 4 * n);
  }
  return texels;
}

} // namespace tftable
} // namespace mcv
