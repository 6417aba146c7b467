// Out-of-sample placement on the GPU: float candidates by a shared-memory tiled kernel,
// then the canonical rule (ExactKnn.h) in double, the bound check, an exact scan for the
// rows that fail it, and the barycentric weights, all on the device.
#include "OutOfSampleCuda.h"

#include "CudaCheck.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

namespace mcv
{
namespace cuda
{

namespace
{
constexpr int KP = 8;          // float candidates per row
constexpr int kThreads = 128;  // rows per block of the candidate kernel
constexpr int kTile = 128;     // references per shared-memory tile
constexpr unsigned kNone = 0xffffffffu;
constexpr std::size_t kChunkRows = std::size_t(1) << 20; // rows per launch (progress steps)
static_assert(kMaxPlacementNeighbors + 2 <= KP, "keep at least two spare candidates");

__constant__ int cColumns[kMaxPlacementDimension];

struct RowParams
{
  const float* rows;
  std::size_t first; // first row of this chunk
  int count;         // rows in this chunk
  int dim;
  int D;
  int gather; // 1: feature c is rows[..][cColumns[c]]
  int M;
};

struct PlaceParams
{
  const float* refX; // M x D
  const float* refY; // M x d
  int D, d, k;
  double regularization;
  double margin;
  float* out;            // n x d
  unsigned* neighbors;   // n x k or null
};

__device__ __forceinline__ float feature(const float* row, int c, int gather)
{
  return row[gather ? cColumns[c] : c];
}

// One query per thread; DP = D padded with zeros (queries and references alike) to a
// multiple of 4 so a reference is read from shared memory as float4 broadcasts.
template <int DP>
__global__ void __launch_bounds__(kThreads) candidatesKernel(
  RowParams p, const float4* __restrict__ refs4, unsigned* __restrict__ cIdx, float* __restrict__ cF)
{
  constexpr int V = DP / 4;
  __shared__ float4 tile[kTile * V];
  const int local = blockIdx.x * kThreads + threadIdx.x;
  const bool active = local < p.count;
  const float* row = p.rows + (p.first + static_cast<std::size_t>(active ? local : 0)) * p.dim;
  float q[DP];
#pragma unroll
  for (int c = 0; c < DP; ++c)
  {
    q[c] = c < p.D ? feature(row, c, p.gather) : 0.f;
  }
  float bf[KP];
  unsigned bi[KP];
#pragma unroll
  for (int s = 0; s < KP; ++s)
  {
    bf[s] = __int_as_float(0x7f800000); // +inf
    bi[s] = kNone;
  }
  for (int base = 0; base < p.M; base += kTile)
  {
    const int n = min(kTile, p.M - base);
    __syncthreads();
    for (int t = threadIdx.x; t < n * V; t += kThreads)
    {
      tile[t] = refs4[static_cast<std::size_t>(base) * V + t];
    }
    __syncthreads();
#pragma unroll 2
    for (int j = 0; j < n; ++j)
    {
      float acc = 0.f;
#pragma unroll
      for (int v = 0; v < V; ++v)
      {
        const float4 r = tile[j * V + v];
        const float t0 = q[4 * v] - r.x;
        const float t1 = q[4 * v + 1] - r.y;
        const float t2 = q[4 * v + 2] - r.z;
        const float t3 = q[4 * v + 3] - r.w;
        acc = fmaf(t0, t0, acc);
        acc = fmaf(t1, t1, acc);
        acc = fmaf(t2, t2, acc);
        acc = fmaf(t3, t3, acc);
      }
      if (acc < bf[KP - 1])
      {
        // Increasing reference index: an equal distance stays behind, so (distance, index).
        bf[KP - 1] = acc;
        bi[KP - 1] = static_cast<unsigned>(base + j);
#pragma unroll
        for (int s = KP - 1; s > 0; --s)
        {
          if (bf[s] < bf[s - 1])
          {
            const float tf = bf[s];
            bf[s] = bf[s - 1];
            bf[s - 1] = tf;
            const unsigned ti = bi[s];
            bi[s] = bi[s - 1];
            bi[s - 1] = ti;
          }
        }
      }
    }
  }
  if (active)
  {
#pragma unroll
    for (int s = 0; s < KP; ++s)
    {
      cIdx[static_cast<std::size_t>(local) * KP + s] = bi[s];
      cF[static_cast<std::size_t>(local) * KP + s] = bf[s];
    }
  }
}

// The canonical distance, rounded step by step exactly like the CPU's (no FMA contraction).
__device__ double canonicalD2(const float* q, const float* r, int D)
{
  double s = 0.0;
  for (int c = 0; c < D; ++c)
  {
    const double t = __dsub_rn(static_cast<double>(q[c]), static_cast<double>(r[c]));
    s = __dadd_rn(s, __dmul_rn(t, t));
  }
  return s;
}

__device__ void loadRow(const RowParams& p, int local, float* q)
{
  const float* row = p.rows + (p.first + static_cast<std::size_t>(local)) * p.dim;
  for (int c = 0; c < p.D; ++c)
  {
    q[c] = feature(row, c, p.gather);
  }
}

// Barycentric weights of the k neighbours (Cholesky of G + ridge) and the coordinates;
// an exact match takes the reference's embedding exactly. Same rules as the CPU path.
__device__ void place(const PlaceParams& pp, std::size_t row, const float* q, const unsigned* nb, const double* d2)
{
  const int k = pp.k;
  float* y = pp.out + row * pp.d;
  if (pp.neighbors)
  {
    for (int j = 0; j < k; ++j)
    {
      pp.neighbors[row * k + j] = nb[j];
    }
  }
  if (k == 1 || d2[0] == 0.0)
  {
    for (int c = 0; c < pp.d; ++c)
    {
      y[c] = pp.refY[static_cast<std::size_t>(nb[0]) * pp.d + c];
    }
    return;
  }
  double G[kMaxPlacementNeighbors][kMaxPlacementNeighbors];
  for (int a = 0; a < k; ++a)
  {
    const float* ra = pp.refX + static_cast<std::size_t>(nb[a]) * pp.D;
    for (int b = 0; b <= a; ++b)
    {
      const float* rb = pp.refX + static_cast<std::size_t>(nb[b]) * pp.D;
      double s = 0.0;
      for (int c = 0; c < pp.D; ++c)
      {
        const double q64 = static_cast<double>(q[c]);
        s += (static_cast<double>(ra[c]) - q64) * (static_cast<double>(rb[c]) - q64);
      }
      G[a][b] = s;
      G[b][a] = s;
    }
  }
  double tr = 0.0;
  for (int a = 0; a < k; ++a)
  {
    tr += G[a][a];
  }
  const double ridge = tr > 0 ? pp.regularization * tr : pp.regularization;
  for (int a = 0; a < k; ++a)
  {
    G[a][a] += ridge;
  }
  // Cholesky G = L L^T (in place, lower triangle), then L L^T w = 1.
  bool ok = true;
  for (int i = 0; i < k; ++i)
  {
    for (int j = 0; j <= i; ++j)
    {
      double s = G[i][j];
      for (int m = 0; m < j; ++m)
      {
        s -= G[i][m] * G[j][m];
      }
      if (i == j)
      {
        ok = ok && s > 0.0;
        G[i][i] = sqrt(s > 0.0 ? s : 1.0);
      }
      else
      {
        G[i][j] = s / G[j][j];
      }
    }
  }
  double w[kMaxPlacementNeighbors];
  for (int i = 0; i < k; ++i)
  {
    double s = 1.0;
    for (int m = 0; m < i; ++m)
    {
      s -= G[i][m] * w[m];
    }
    w[i] = s / G[i][i];
  }
  for (int i = k - 1; i >= 0; --i)
  {
    double s = w[i];
    for (int m = i + 1; m < k; ++m)
    {
      s -= G[m][i] * w[m];
    }
    w[i] = s / G[i][i];
  }
  double sum = 0.0;
  for (int i = 0; i < k; ++i)
  {
    sum += w[i];
  }
  if (!ok || !isfinite(sum) || sum == 0.0)
  {
    for (int i = 0; i < k; ++i)
    {
      w[i] = 1.0;
    }
    sum = k;
  }
  for (int c = 0; c < pp.d; ++c)
  {
    double v = 0.0;
    for (int j = 0; j < k; ++j)
    {
      v += w[j] * static_cast<double>(pp.refY[static_cast<std::size_t>(nb[j]) * pp.d + c]);
    }
    y[c] = static_cast<float>(v / sum);
  }
}

// Canonical rule on the candidates, the bound check, placement; failing rows are listed.
__global__ void resolveKernel(RowParams p, PlaceParams pp, const unsigned* __restrict__ cIdx,
  const float* __restrict__ cF, unsigned* __restrict__ scanRows, unsigned* __restrict__ scanCount)
{
  const int local = blockIdx.x * blockDim.x + threadIdx.x;
  if (local >= p.count)
  {
    return;
  }
  float q[kMaxPlacementDimension];
  loadRow(p, local, q);
  double cd[KP];
  unsigned ci[KP];
  int valid = 0;
  for (int s = 0; s < KP; ++s)
  {
    const unsigned idx = cIdx[static_cast<std::size_t>(local) * KP + s];
    if (idx == kNone)
    {
      break;
    }
    const double d = canonicalD2(q, pp.refX + static_cast<std::size_t>(idx) * pp.D, pp.D);
    int at = valid++;
    while (at > 0 && (cd[at - 1] > d || (cd[at - 1] == d && ci[at - 1] > idx)))
    {
      cd[at] = cd[at - 1];
      ci[at] = ci[at - 1];
      --at;
    }
    cd[at] = d;
    ci[at] = idx;
  }
  const double grow = (1.0 + pp.margin) * (1.0 + pp.margin);
  const bool exact = valid >= pp.k &&
    (valid == p.M || static_cast<double>(cF[static_cast<std::size_t>(local) * KP + valid - 1]) > cd[pp.k - 1] * grow);
  if (!exact)
  {
    scanRows[atomicAdd(scanCount, 1u)] = static_cast<unsigned>(local);
    return;
  }
  place(pp, p.first + local, q, ci, cd);
}

// The rows the bound could not settle: every reference in canonical double, best k kept
// by (distance, index).
__global__ void scanKernel(RowParams p, PlaceParams pp, const unsigned* __restrict__ scanRows, unsigned count)
{
  const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= count)
  {
    return;
  }
  const int local = static_cast<int>(scanRows[t]);
  float q[kMaxPlacementDimension];
  loadRow(p, local, q);
  double bd[kMaxPlacementNeighbors];
  unsigned bi[kMaxPlacementNeighbors];
  for (int j = 0; j < pp.k; ++j)
  {
    bd[j] = __longlong_as_double(0x7ff0000000000000ll); // +inf
    bi[j] = kNone;
  }
  for (int r = 0; r < p.M; ++r)
  {
    const double d = canonicalD2(q, pp.refX + static_cast<std::size_t>(r) * pp.D, pp.D);
    if (d < bd[pp.k - 1])
    {
      int at = pp.k - 1;
      while (at > 0 && bd[at - 1] > d)
      {
        bd[at] = bd[at - 1];
        bi[at] = bi[at - 1];
        --at;
      }
      bd[at] = d;
      bi[at] = static_cast<unsigned>(r);
    }
  }
  place(pp, p.first + local, q, bi, bd);
}

struct DeviceBuffer
{
  void* ptr = nullptr;
  ~DeviceBuffer()
  {
    if (ptr)
    {
      cudaFree(ptr);
    }
  }
  template <class T>
  T* as() const
  {
    return static_cast<T*>(ptr);
  }
};

template <int DP>
void launchCandidates(const RowParams& p, const float* refsPadded, unsigned* cIdx, float* cF)
{
  const int blocks = (p.count + kThreads - 1) / kThreads;
  candidatesKernel<DP><<<blocks, kThreads>>>(p, reinterpret_cast<const float4*>(refsPadded), cIdx, cF);
}

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
} // namespace

bool placeOutOfSample(const PlacementInput& in, float* out, std::uint32_t* neighbors,
  const std::function<void(double)>& progress, PlacementStats* stats, std::string* error)
{
  FaultStage stage("outofsample");
  if (in.D < 1 || in.D > kMaxPlacementDimension)
  {
    return detail::fail(error, "the GPU placement handles 1.." + std::to_string(kMaxPlacementDimension) +
        " features (got " + std::to_string(in.D) + ")");
  }
  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, in.neighbors)), in.M));
  if (k > kMaxPlacementNeighbors)
  {
    return detail::fail(error, "the GPU placement handles up to " + std::to_string(kMaxPlacementNeighbors) +
        " neighbours (got " + std::to_string(k) + ")");
  }
  if (in.M == 0 || in.M >= 0x7fffffffu || (in.columns == nullptr && in.dim != in.D) || in.d < 1)
  {
    return detail::fail(error, "invalid GPU placement arguments");
  }
  if (in.n == 0)
  {
    return true;
  }
  const int DP = in.D <= 8 ? 8 : in.D <= 16 ? 16 : in.D <= 24 ? 24 : in.D <= 32 ? 32 : in.D <= 48 ? 48 : 64;
  PlacementStats local;
  PlacementStats& st = stats ? *stats : local;
  st = PlacementStats{};

  auto start = Clock::now();
  std::vector<float> padded(in.M * static_cast<std::size_t>(DP), 0.f);
  for (std::size_t i = 0; i < in.M; ++i)
  {
    std::copy(in.refX + i * in.D, in.refX + (i + 1) * in.D, padded.begin() + static_cast<std::ptrdiff_t>(i * DP));
  }
  const std::size_t chunk = std::min(kChunkRows, in.n);
  DeviceBuffer dRows, dRefs, dRefX, dRefY, dOut, dNb, dCIdx, dCF, dScan, dScanCount;
  MCV_CUDA_TRY(cudaMalloc(&dRows.ptr, in.n * in.dim * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dRefs.ptr, padded.size() * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dRefX.ptr, in.M * in.D * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dRefY.ptr, in.M * in.d * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dOut.ptr, in.n * in.d * sizeof(float)));
  if (neighbors)
  {
    MCV_CUDA_TRY(cudaMalloc(&dNb.ptr, in.n * k * sizeof(unsigned)));
  }
  MCV_CUDA_TRY(cudaMalloc(&dCIdx.ptr, chunk * KP * sizeof(unsigned)));
  MCV_CUDA_TRY(cudaMalloc(&dCF.ptr, chunk * KP * sizeof(float)));
  MCV_CUDA_TRY(cudaMalloc(&dScan.ptr, chunk * sizeof(unsigned)));
  MCV_CUDA_TRY(cudaMalloc(&dScanCount.ptr, sizeof(unsigned)));
  if (in.columns)
  {
    MCV_CUDA_TRY(cudaMemcpyToSymbol(cColumns, in.columns, in.D * sizeof(int)));
  }
  MCV_CUDA_TRY(cudaMemcpy(dRows.ptr, in.rows, in.n * in.dim * sizeof(float), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemcpy(dRefs.ptr, padded.data(), padded.size() * sizeof(float), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemcpy(dRefX.ptr, in.refX, in.M * in.D * sizeof(float), cudaMemcpyHostToDevice));
  MCV_CUDA_TRY(cudaMemcpy(dRefY.ptr, in.refY, in.M * in.d * sizeof(float), cudaMemcpyHostToDevice));
  st.uploadMs = msSince(start);

  start = Clock::now();
  RowParams p{ dRows.as<float>(), 0, 0, in.dim, in.D, in.columns ? 1 : 0, static_cast<int>(in.M) };
  PlaceParams pp{ dRefX.as<float>(), dRefY.as<float>(), in.D, in.d, k, in.regularization, in.distanceMargin,
    dOut.as<float>(), neighbors ? dNb.as<unsigned>() : nullptr };
  for (std::size_t first = 0; first < in.n; first += chunk)
  {
    p.first = first;
    p.count = static_cast<int>(std::min(chunk, in.n - first));
    MCV_CUDA_TRY(cudaMemsetAsync(dScanCount.ptr, 0, sizeof(unsigned)));
    switch (DP)
    {
      case 8:
        launchCandidates<8>(p, dRefs.as<float>(), dCIdx.as<unsigned>(), dCF.as<float>());
        break;
      case 16:
        launchCandidates<16>(p, dRefs.as<float>(), dCIdx.as<unsigned>(), dCF.as<float>());
        break;
      case 24:
        launchCandidates<24>(p, dRefs.as<float>(), dCIdx.as<unsigned>(), dCF.as<float>());
        break;
      case 32:
        launchCandidates<32>(p, dRefs.as<float>(), dCIdx.as<unsigned>(), dCF.as<float>());
        break;
      case 48:
        launchCandidates<48>(p, dRefs.as<float>(), dCIdx.as<unsigned>(), dCF.as<float>());
        break;
      default:
        launchCandidates<64>(p, dRefs.as<float>(), dCIdx.as<unsigned>(), dCF.as<float>());
        break;
    }
    MCV_CUDA_TRY(cudaGetLastError());
    const int blocks = (p.count + 127) / 128;
    resolveKernel<<<blocks, 128>>>(p, pp, dCIdx.as<unsigned>(), dCF.as<float>(), dScan.as<unsigned>(),
      dScanCount.as<unsigned>());
    MCV_CUDA_TRY(cudaGetLastError());
    unsigned scans = 0;
    MCV_CUDA_TRY(cudaMemcpy(&scans, dScanCount.ptr, sizeof(unsigned), cudaMemcpyDeviceToHost));
    if (scans > 0)
    {
      scanKernel<<<(scans + 63) / 64, 64>>>(p, pp, dScan.as<unsigned>(), scans);
      MCV_CUDA_TRY(cudaGetLastError());
      st.radiusScans += scans;
    }
    if (progress)
    {
      MCV_CUDA_TRY(cudaDeviceSynchronize());
      progress(static_cast<double>(first + p.count) / static_cast<double>(in.n));
    }
  }
  MCV_CUDA_TRY(cudaDeviceSynchronize());
  st.computeMs = msSince(start);

  start = Clock::now();
  MCV_CUDA_TRY(cudaMemcpy(out, dOut.ptr, in.n * in.d * sizeof(float), cudaMemcpyDeviceToHost));
  if (neighbors)
  {
    MCV_CUDA_TRY(cudaMemcpy(neighbors, dNb.ptr, in.n * k * sizeof(unsigned), cudaMemcpyDeviceToHost));
  }
  st.downloadMs = msSince(start);
  return true;
}

} // namespace cuda
} // namespace mcv
