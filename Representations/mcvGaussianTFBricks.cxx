#include "mcvGaussianTFBricks.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace mcv
{
namespace bricks
{

BrickBounds computeBrickBounds(const std::uint16_t* texels, const int dims[3])
{
  BrickBounds result;
  for (int a = 0; a < 3; ++a)
  {
    result.volume[a] = dims[a];
    result.grid[a] = std::max(1, (dims[a] + BrickSize - 1) / BrickSize);
  }
  const size_t bricks = static_cast<size_t>(result.Count());
  result.low.assign(bricks * 3, 2.0f);
  result.high.assign(bricks * 3, -1.0f);
  const float scale = 1.0f / 65535.0f;
  for (int k = 0; k < dims[2]; ++k)
  {
    // A voxel on a brick's low face is also the last (interpolated) voxel of the brick before.
    const int bz1 = std::min(k / BrickSize, result.grid[2] - 1);
    const int bz0 = (k % BrickSize == 0 && k > 0) ? bz1 - 1 : bz1;
    for (int j = 0; j < dims[1]; ++j)
    {
      const int by1 = std::min(j / BrickSize, result.grid[1] - 1);
      const int by0 = (j % BrickSize == 0 && j > 0) ? by1 - 1 : by1;
      const std::uint16_t* row = texels + 4 * (static_cast<size_t>(k) * dims[1] + j) * dims[0];
      for (int i = 0; i < dims[0]; ++i)
      {
        const std::uint16_t* t = row + 4 * static_cast<size_t>(i);
        if (t[3] == 0)
        {
          continue;
        }
        const float x[3] = { t[0] * scale, t[1] * scale, t[2] * scale };
        const int bx1 = std::min(i / BrickSize, result.grid[0] - 1);
        const int bx0 = (i % BrickSize == 0 && i > 0) ? bx1 - 1 : bx1;
        for (int bz = bz0; bz <= bz1; ++bz)
        {
          for (int by = by0; by <= by1; ++by)
          {
            for (int bx = bx0; bx <= bx1; ++bx)
            {
              const size_t b = 3 * ((static_cast<size_t>(bz) * result.grid[1] + by) * result.grid[0] + bx);
              for (int a = 0; a < 3; ++a)
              {
                result.low[b + a] = std::min(result.low[b + a], x[a]);
                result.high[b + a] = std::max(result.high[b + a], x[a]);
              }
            }
          }
        }
      }
    }
  }
  return result;
}

std::vector<float> buildWidgetTable(const BrickBounds& bounds,
  const std::vector<mcv::detail::PackedGaussianWidget>& widgets, const float minimum[3],
  const float extent[3], int& height, int& emptyBricks, long long& listedWidgets)
{
  const int bricks = bounds.Count();
  const double logCutoff = std::log(Cutoff);
  std::vector<float> table(2 * static_cast<size_t>(1 + bricks), 0.0f);
  table[0] = CheckValue;
  std::vector<float> lists;
  std::map<std::vector<std::uint8_t>, int> starts; // identical lists stored once
  std::vector<std::uint8_t> list;
  emptyBricks = 0;
  listedWidgets = 0;
  for (int b = 0; b < bricks; ++b)
  {
    list.clear();
    const float* low = &bounds.low[3 * static_cast<size_t>(b)];
    const float* high = &bounds.high[3 * static_cast<size_t>(b)];
    if (low[0] <= high[0])
    {
      double lo[3], hi[3];
      for (int a = 0; a < 3; ++a)
      {
        lo[a] = minimum[a] + extent[a] * static_cast<double>(low[a]);
        hi[a] = minimum[a] + extent[a] * static_cast<double>(high[a]);
      }
      for (size_t w = 0; w < widgets.size(); ++w)
      {
        const double centre[3] = { widgets[w].cx, widgets[w].cy, widgets[w].cz };
        double d2 = 0;
        for (int a = 0; a < 3; ++a)
        {
          const double d = std::max({ lo[a] - centre[a], 0.0, centre[a] - hi[a] });
          d2 += d * d;
        }
        if (widgets[w].logA - widgets[w].k * d2 > logCutoff)
        {
          list.push_back(static_cast<std::uint8_t>(w));
        }
      }
    }
    float* entry = &table[2 * static_cast<size_t>(1 + b)];
    if (list.empty())
    {
      ++emptyBricks;
      continue;
    }
    if (list.size() * ListShare > widgets.size())
    {
      // Most widgets reach it: all of them, in order (cheaper per widget than a list).
      listedWidgets += static_cast<long long>(widgets.size());
      entry[0] = -1.0f;
      entry[1] = static_cast<float>(widgets.size());
      continue;
    }
    listedWidgets += static_cast<long long>(list.size());
    auto found = starts.find(list);
    int start = 0;
    if (found != starts.end())
    {
      start = found->second;
    }
    else
    {
      start = 1 + bricks + static_cast<int>(lists.size());
      starts.emplace(list, start);
      lists.insert(lists.end(), list.begin(), list.end());
    }
    entry[0] = static_cast<float>(start);
    entry[1] = static_cast<float>(list.size());
  }
  for (float w : lists)
  {
    table.push_back(w);
    table.push_back(0.0f);
  }
  const size_t entries = table.size() / 2;
  height = static_cast<int>((entries + TableWidth - 1) / TableWidth);
  table.resize(2 * static_cast<size_t>(height) * TableWidth, 0.0f);
  return table;
}

} // namespace bricks
} // namespace mcv
