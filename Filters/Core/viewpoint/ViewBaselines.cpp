// Baseline viewpoint methods (dissertation section 7.5): area maximising and viewpoint
// (opacity) entropy with a small CPU ray caster. See ViewBaselines.h.
//
// Conventions shared by both baselines (and documented for the filter and Python helper):
// - Voxel footprint. A voxel is a cell of size `spacing` centred on its world position, so
//   the tight box of the voxels i0..i1 along x is (i1 - i0 + 1) * spacing[0] wide and a
//   single slice is one spacing thick (its normal is then the area-maximising answer).
//   The ray caster samples the same footprint: trilinear inside the voxel-centre bounds,
//   clamped to the edge values in the half voxel around them.
// - center: the centre of the volume (of its voxel-centre bounds), not of the visible part.
// - viewUp: +z made orthogonal to `best` (Gram-Schmidt), or +y when |best.z| > 0.9. Stable
//   (the same best gives the same up; it changes only when best crosses |z| = 0.9), unit,
//   orthogonal to best, and "z up" for the usual medical orientation.
// - eigenvalues: left 0 (they belong to the Harris/PCA method).
// - best/worst of the area-maximising view have non-negative components (u = (hd,dw,wh)/K
//   and a coordinate axis), which is also the largest-component-positive sign convention
//   of ViewFromPoints.h. The entropy baseline keeps the sampled direction as it is: a
//   sample and its antipode are different views (front-to-back compositing is not
//   symmetric), so `best` is the direction the camera looks along.
#include "ViewBaselines.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

namespace mcv
{
namespace
{

double dot(const Vec3& a, const Vec3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec3 cross(const Vec3& a, const Vec3& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

bool normalize(Vec3& v)
{
  const double n = std::sqrt(dot(v, v));
  if (!(n > 0) || !std::isfinite(n))
    return false;
  for (double& c : v)
    c /= n;
  return true;
}

// +z orthogonalised against d, or +y when d is within ~25 degrees of the z axis.
Vec3 stableViewUp(const Vec3& d)
{
  Vec3 up = std::fabs(d[2]) > 0.9 ? Vec3{ 0, 1, 0 } : Vec3{ 0, 0, 1 };
  const double p = dot(up, d);
  for (int a = 0; a < 3; ++a)
    up[a] -= p * d[a];
  normalize(up);
  return up;
}

// Returns an empty string when the grid and pointer can be used, else what is wrong.
std::string checkGrid(const float* opacity, const ImageGrid& grid)
{
  if (!opacity)
    return "no opacity values (null pointer)";
  for (int a = 0; a < 3; ++a)
  {
    if (grid.dims[a] < 1)
    {
      std::ostringstream s;
      s << "empty volume (dimensions " << grid.dims[0] << " x " << grid.dims[1] << " x "
        << grid.dims[2] << ")";
      return s.str();
    }
    if (!(grid.spacing[a] > 0) || !std::isfinite(grid.spacing[a]))
    {
      std::ostringstream s;
      s << "invalid spacing " << grid.spacing[a] << " along axis " << a
        << " (must be positive and finite)";
      return s.str();
    }
    if (!std::isfinite(grid.origin[a]))
      return "invalid (non-finite) origin";
  }
  return std::string();
}

Vec3 volumeCenter(const ImageGrid& grid)
{
  return { grid.origin[0] + 0.5 * grid.spacing[0] * (grid.dims[0] - 1),
    grid.origin[1] + 0.5 * grid.spacing[1] * (grid.dims[1] - 1),
    grid.origin[2] + 0.5 * grid.spacing[2] * (grid.dims[2] - 1) };
}

ViewDirections invalidView(const ImageGrid& grid, std::string message)
{
  ViewDirections v;
  v.valid = false;
  v.message = std::move(message);
  bool gridOk = true;
  for (int a = 0; a < 3; ++a)
    gridOk = gridOk && grid.dims[a] >= 1 && std::isfinite(grid.spacing[a]) &&
      std::isfinite(grid.origin[a]);
  if (gridOk)
    v.center = volumeCenter(grid);
  return v;
}

// Radius of the sphere around the voxel footprint box (half its diagonal).
double boundingRadius(const ImageGrid& grid)
{
  double r2 = 0;
  for (int a = 0; a < 3; ++a)
  {
    const double e = 0.5 * grid.dims[a] * grid.spacing[a];
    r2 += e * e;
  }
  return std::sqrt(r2);
}

// Empty-space skipping: bricks of kBrick^3 cells. A brick is empty when every voxel that a
// trilinear sample within one voxel of it can read (its voxels plus an apron of one voxel
// on the - side and two on the + side) has opacity <= 0 or NaN: such samples are <= 0 or
// NaN and add nothing, so skipping them leaves the image bit-identical.
constexpr int kBrick = 8;

struct BrickMap
{
  int bx = 0, by = 0, bz = 0;
  std::vector<unsigned char> occupied; // bx * by * bz, x fastest
  bool at(int i, int j, int k) const
  {
    return occupied[(static_cast<std::size_t>(k / kBrick) * by + j / kBrick) * bx + i / kBrick] != 0;
  }
};

BrickMap buildBrickMap(const float* opacity, const ImageGrid& grid)
{
  BrickMap m;
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  m.bx = (nx + kBrick - 1) / kBrick;
  m.by = (ny + kBrick - 1) / kBrick;
  m.bz = (nz + kBrick - 1) / kBrick;
  m.occupied.assign(static_cast<std::size_t>(m.bx) * m.by * m.bz, 0);
#pragma omp parallel for schedule(dynamic, 1)
  for (int bk = 0; bk < m.bz; ++bk)
    for (int bj = 0; bj < m.by; ++bj)
      for (int bi = 0; bi < m.bx; ++bi)
      {
        bool any = false;
        const int k0 = std::max(0, bk * kBrick - 1), k1 = std::min(nz - 1, (bk + 1) * kBrick + 1);
        const int j0 = std::max(0, bj * kBrick - 1), j1 = std::min(ny - 1, (bj + 1) * kBrick + 1);
        const int i0 = std::max(0, bi * kBrick - 1), i1 = std::min(nx - 1, (bi + 1) * kBrick + 1);
        for (int k = k0; k <= k1 && !any; ++k)
          for (int j = j0; j <= j1 && !any; ++j)
          {
            const float* row = opacity + (static_cast<std::size_t>(k) * ny + j) * nx;
            for (int i = i0; i <= i1; ++i)
              if (row[i] > 0.0f)
              {
                any = true;
                break;
              }
          }
        m.occupied[(static_cast<std::size_t>(bk) * m.by + bj) * m.bx + bi] = any ? 1 : 0;
      }
  return m;
}

// The ray caster. Writes imageSize^2 accumulated opacities into `image` (row-major,
// row 0 at the bottom: pixel (px, py) is at centre + x * right + y * up).
void castImage(const float* opacity, const ImageGrid& grid, const BrickMap& bricks,
  const Vec3& dirIn, int imageSize, float* image)
{
  const std::size_t pixels = static_cast<std::size_t>(imageSize) * imageSize;
  std::fill(image, image + pixels, 0.0f);
  Vec3 d = dirIn;
  if (!normalize(d))
    return;
  const Vec3 up = stableViewUp(d);
  const Vec3 right = cross(d, up);
  const Vec3 c = volumeCenter(grid);
  const double R = boundingRadius(grid);
  const double pixel = 2.0 * R / imageSize;
  const double minSpacing = std::min(grid.spacing[0], std::min(grid.spacing[1], grid.spacing[2]));
  const double step = 0.5 * minSpacing; // world units
  // Opacity correction: the transfer function's opacity is per voxel (one smallest
  // spacing) of travel; a sample step of `step` gets 1 - (1 - a)^(step / minSpacing).
  const float exponent = static_cast<float>(step / minSpacing);
  const bool halfStep = exponent == 0.5f; // the usual case: a square root, not pow

  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  const std::int64_t sx = 1, sy = nx, sz = static_cast<std::int64_t>(nx) * ny;
  // Step in voxel coordinates.
  const double dv[3] = { d[0] * step / grid.spacing[0], d[1] * step / grid.spacing[1],
    d[2] * step / grid.spacing[2] };
  const double lo[3] = { -0.5, -0.5, -0.5 };
  const double hi[3] = { nx - 0.5, ny - 0.5, nz - 0.5 };
  const float maxC[3] = { static_cast<float>(nx - 1), static_cast<float>(ny - 1),
    static_cast<float>(nz - 1) };

#pragma omp parallel for schedule(dynamic, 4)
  for (int py = 0; py < imageSize; ++py)
  {
    const double y = (py + 0.5) * pixel - R;
    for (int px = 0; px < imageSize; ++px)
    {
      const double x = (px + 0.5) * pixel - R;
      // Ray start (world) on the near side of the bounding sphere, in voxel coordinates.
      double p0[3];
      for (int a = 0; a < 3; ++a)
      {
        const double w = c[a] - R * d[a] + x * right[a] + y * up[a];
        p0[a] = (w - grid.origin[a]) / grid.spacing[a];
      }
      // Clip the ray p0 + s * dv (s in steps) to the footprint box.
      double s0 = 0.0, s1 = 2.0 * R / step;
      bool miss = false;
      for (int a = 0; a < 3 && !miss; ++a)
      {
        if (std::fabs(dv[a]) < 1e-12)
        {
          if (p0[a] < lo[a] || p0[a] > hi[a])
            miss = true;
          continue;
        }
        double ta = (lo[a] - p0[a]) / dv[a], tb = (hi[a] - p0[a]) / dv[a];
        if (ta > tb)
          std::swap(ta, tb);
        s0 = std::max(s0, ta);
        s1 = std::min(s1, tb);
        if (s0 > s1)
          miss = true;
      }
      if (miss)
        continue;
      // Samples at the middle of each step inside [s0, s1].
      const long kBegin = static_cast<long>(std::ceil(s0 - 0.5));
      const long kEnd = static_cast<long>(std::floor(s1 - 0.5)); // inclusive
      float acc = 0.0f;
      for (long k = std::max(0L, kBegin); k <= kEnd;)
      {
        const double s = k + 0.5;
        float fx = static_cast<float>(p0[0] + s * dv[0]);
        float fy = static_cast<float>(p0[1] + s * dv[1]);
        float fz = static_cast<float>(p0[2] + s * dv[2]);
        fx = std::min(std::max(fx, 0.0f), maxC[0]);
        fy = std::min(std::max(fy, 0.0f), maxC[1]);
        fz = std::min(std::max(fz, 0.0f), maxC[2]);
        const int i0 = static_cast<int>(fx), j0 = static_cast<int>(fy), k0 = static_cast<int>(fz);
        if (!bricks.at(i0, j0, k0))
        {
          // Jump to the first sample past this brick (at least one step): the samples in
          // between read only transparent voxels.
          const int b[3] = { i0 / kBrick, j0 / kBrick, k0 / kBrick };
          double exitS = std::numeric_limits<double>::infinity();
          for (int a = 0; a < 3; ++a)
          {
            if (dv[a] > 1e-12)
              exitS = std::min(exitS, ((b[a] + 1) * kBrick - p0[a]) / dv[a]);
            else if (dv[a] < -1e-12)
              exitS = std::min(exitS, (b[a] * kBrick - p0[a]) / dv[a]);
          }
          // First sample at or past the boundary. Samples before it lie inside the brick
          // up to float rounding, far less than the apron of one voxel on each side.
          const double next = std::ceil(exitS - 0.5);
          k = next > static_cast<double>(kEnd) ? kEnd + 1
                                                : std::max(k + 1, static_cast<long>(next));
          continue;
        }
        ++k;
        const float tx = fx - i0, ty = fy - j0, tz = fz - k0;
        const std::int64_t ox = i0 + 1 < nx ? sx : 0;
        const std::int64_t oy = j0 + 1 < ny ? sy : 0;
        const std::int64_t oz = k0 + 1 < nz ? sz : 0;
        const float* v = opacity + i0 * sx + j0 * sy + k0 * sz;
        const float c00 = v[0] + tx * (v[ox] - v[0]);
        const float c10 = v[oy] + tx * (v[oy + ox] - v[oy]);
        const float c01 = v[oz] + tx * (v[oz + ox] - v[oz]);
        const float c11 = v[oz + oy] + tx * (v[oz + oy + ox] - v[oz + oy]);
        const float c0 = c00 + ty * (c10 - c00);
        const float c1 = c01 + ty * (c11 - c01);
        float a = c0 + tz * (c1 - c0);
        if (!(a > 0.0f)) // also NaN
          continue;
        if (a >= 1.0f)
          a = 1.0f;
        else
          a = halfStep ? 1.0f - std::sqrt(1.0f - a) : 1.0f - std::pow(1.0f - a, exponent);
        acc += (1.0f - acc) * a;
        if (acc >= 0.99f) // early ray termination
          break;
      }
      image[static_cast<std::size_t>(py) * imageSize + px] = acc;
    }
  }
}

// Fibonacci sphere: n near-uniform unit directions (z from +1 to -1).
Vec3 fibonacciDirection(int i, int n)
{
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  const double z = 1.0 - (2.0 * i + 1.0) / n;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = golden * i;
  return { r * std::cos(phi), r * std::sin(phi), z };
}

} // namespace

ViewDirections areaMaximizingView(const float* opacity, const ImageGrid& grid, float threshold)
{
  const std::string bad = checkGrid(opacity, grid);
  if (!bad.empty())
    return invalidView(grid, "area maximising view: " + bad);

  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  int lo[3] = { nx, ny, nz }, hi[3] = { -1, -1, -1 };
#pragma omp parallel
  {
    int tlo[3] = { nx, ny, nz }, thi[3] = { -1, -1, -1 };
#pragma omp for schedule(static) nowait
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
      {
        const float* row = opacity + (static_cast<std::size_t>(k) * ny + j) * nx;
        int first = -1, last = -1;
        for (int i = 0; i < nx; ++i)
          if (row[i] > threshold && std::isfinite(row[i]))
          {
            first = i;
            break;
          }
        if (first < 0)
          continue;
        for (int i = nx - 1; i >= first; --i)
          if (row[i] > threshold && std::isfinite(row[i]))
          {
            last = i;
            break;
          }
        tlo[0] = std::min(tlo[0], first);
        thi[0] = std::max(thi[0], last);
        tlo[1] = std::min(tlo[1], j);
        thi[1] = std::max(thi[1], j);
        tlo[2] = std::min(tlo[2], k);
        thi[2] = std::max(thi[2], k);
      }
#pragma omp critical(mcv_area_bbox)
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::min(lo[a], tlo[a]);
      hi[a] = std::max(hi[a], thi[a]);
    }
  }
  if (hi[0] < 0)
  {
    std::ostringstream s;
    s << "area maximising view: no voxel has opacity above " << threshold
      << " (fully transparent volume)";
    return invalidView(grid, s.str());
  }

  // Tight box in world units (voxel footprints): w along x, h along y, d along z.
  const double w = (hi[0] - lo[0] + 1) * grid.spacing[0];
  const double h = (hi[1] - lo[1] + 1) * grid.spacing[1];
  const double d = (hi[2] - lo[2] + 1) * grid.spacing[2];
  const double area[3] = { h * d, d * w, w * h }; // face areas seen along x, y, z
  const double K = std::sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);

  ViewDirections v;
  v.center = volumeCenter(grid);
  if (!(K > 0) || !std::isfinite(K))
  {
    v.message = "area maximising view: degenerate bounding box";
    return v;
  }
  v.best = { area[0] / K, area[1] / K, area[2] / K };
  int smallest = 0;
  for (int a = 1; a < 3; ++a)
    if (area[a] < area[smallest])
      smallest = a;
  v.worst = { 0, 0, 0 };
  v.worst[smallest] = 1.0;
  v.viewUp = stableViewUp(v.best);
  v.valid = true;
  return v;
}

std::vector<float> renderOpacityImage(
  const float* opacity, const ImageGrid& grid, const Vec3& direction, int imageSize)
{
  if (imageSize <= 0)
    return {};
  std::vector<float> image(static_cast<std::size_t>(imageSize) * imageSize, 0.0f);
  if (!checkGrid(opacity, grid).empty())
    return image;
  castImage(opacity, grid, buildBrickMap(opacity, grid), direction, imageSize, image.data());
  return image;
}

double imageEntropy(const float* pixels, std::size_t count)
{
  if (!pixels)
    return 0.0;
  double sum = 0;
  for (std::size_t i = 0; i < count; ++i)
    if (pixels[i] > 0 && std::isfinite(pixels[i]))
      sum += pixels[i];
  if (!(sum > 0) || !std::isfinite(sum))
    return 0.0;
  double h = 0;
  for (std::size_t i = 0; i < count; ++i)
    if (pixels[i] > 0 && std::isfinite(pixels[i]))
    {
      const double p = pixels[i] / sum;
      h -= p * std::log2(p);
    }
  return std::max(0.0, h);
}

ViewDirections viewpointEntropyView(const float* opacity, const ImageGrid& grid,
  const EntropyOptions& options, const std::function<void(double)>& progress)
{
  const std::string bad = checkGrid(opacity, grid);
  if (!bad.empty())
    return invalidView(grid, "viewpoint entropy: " + bad);
  if (options.samples < 1)
    return invalidView(grid,
      "viewpoint entropy: the number of view samples must be >= 1 (got " +
        std::to_string(options.samples) + ")");
  if (options.imageSize < 1)
    return invalidView(grid,
      "viewpoint entropy: the image size must be >= 1 pixel (got " +
        std::to_string(options.imageSize) + ")");

  // A volume without any positive opacity renders blank from everywhere.
  const std::size_t n = grid.voxelCount();
  bool any = false;
  for (std::size_t i = 0; i < n && !any; ++i)
    any = opacity[i] > 0.0f && std::isfinite(opacity[i]);
  if (!any)
  {
    if (progress)
      progress(1.0);
    return invalidView(grid,
      "viewpoint entropy: no voxel has positive opacity (fully transparent volume)");
  }

  const int S = options.samples;
  const std::size_t pixels = static_cast<std::size_t>(options.imageSize) * options.imageSize;
  std::vector<float> image(pixels);
  const BrickMap bricks = buildBrickMap(opacity, grid);
  int bestIndex = -1, worstIndex = -1;
  double bestH = -1, worstH = std::numeric_limits<double>::infinity();
  for (int i = 0; i < S; ++i)
  {
    const Vec3 dir = fibonacciDirection(i, S);
    castImage(opacity, grid, bricks, dir, options.imageSize, image.data());
    const double H = imageEntropy(image.data(), pixels);
    if (H > bestH) // ties: the lowest sample index
    {
      bestH = H;
      bestIndex = i;
    }
    if (H < worstH)
    {
      worstH = H;
      worstIndex = i;
    }
    if (progress)
      progress(static_cast<double>(i + 1) / S);
  }

  ViewDirections v;
  v.center = volumeCenter(grid);
  v.best = fibonacciDirection(bestIndex, S);
  v.worst = fibonacciDirection(worstIndex, S);
  normalize(v.best);
  normalize(v.worst);
  v.viewUp = stableViewUp(v.best);
  v.valid = true;
  if (!(bestH > 0))
    v.message = "viewpoint entropy: every image has zero entropy (at most one visible pixel)";
  return v;
}

} // namespace mcv
