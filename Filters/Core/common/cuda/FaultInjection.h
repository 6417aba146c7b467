// Fault injection for the CUDA paths: makes one chosen CUDA call fail with
// cudaErrorMemoryAllocation (without running it), so that tests on a real GPU can check
// that a failure at any point falls back to the CPU cleanly. Plain C++ (no CUDA types).
//
// What is counted: every call checked by MCV_CUDA_TRY (CudaCheck.h) made while a
// FaultStage is alive on the calling thread. The stages are the GPU paths' entry points:
//   harris       best viewpoint: Harris response + top-N (HarrisCuda.h, HarrisPipeline.h)
//   features     feature vectors (FeaturesCuda.h)
//   gaussiantf   Gaussian-widget transfer function (GaussianTFCuda.h)
//   outofsample  out-of-sample placement (OutOfSampleCuda.h)
//   umaplayout   UMAP's SGD layout (UMAPLayoutCuda.h)
//   fused        the fused reduction's slabs: features + placement (FusedPlacementCuda.h)
//   fusedpasses  its statistics, column-sum and strata passes (FusedPassesCuda.h)
//   samplekeys   the reference sample's key scans (SampleKeysCuda.h)
//   isomapfit    Isomap's shortest paths and MDS eigenvalues (GeodesicsCuda.h)
// The kinds of call (from the checked expression's text, at compile time):
//   alloc   cudaMalloc*                     copy  cudaMemcpy*, cudaMemset*
//   launch  the check after a kernel launch, CUB calls, launch helpers
//   sync    cudaStream/Event/DeviceSynchronize           other  anything else
//   any     every checked call
//
// From the environment, read once at the first stage or call below (which then overrides it):
//   MCV_CUDA_FAIL_AT=<stage>:<n>          the n-th allocation of <stage> fails
//   MCV_CUDA_FAIL_AT=<stage>:<kind>:<n>   the n-th call of <kind> in <stage> fails
// An injection fires once and is then off, like a transient out-of-memory. Unset, the
// cost is one relaxed atomic load per checked CUDA call.
#pragma once

#include <atomic>
#include <string>

namespace mcv
{
namespace cuda
{

enum class CudaCall
{
  Any = 0,
  Alloc,
  Copy,
  Launch,
  Sync,
  Other
};

const char* cudaCallName(CudaCall kind);

// Arms one injected failure: counting starts now at 0; the n-th (1-based) call of `kind`
// made inside `stage` reports cudaErrorMemoryAllocation. Replaces an armed one.
void injectFailure(const std::string& stage, CudaCall kind, long n);
// The same from "<stage>:<n>" or "<stage>:<kind>:<n>" (the MCV_CUDA_FAIL_AT syntax).
// False (and nothing armed) with `error` set on a malformed spec or an unknown stage.
bool injectFailure(const std::string& spec, std::string* error = nullptr);
// Disarms a pending injection (one that has not fired).
void clearInjectedFailure();
// Whether an armed injection has not fired yet.
bool failurePending();
// Injected failures so far in this process.
long injectedFailureCount();

// Call counting, to find the injection points of a run: starts (from 0) or stops counting.
void countCudaCalls(bool on);
// Calls of `kind` made inside `stage` since counting started.
long countedCudaCalls(const std::string& stage, CudaCall kind);

// Marks the calling thread as inside `stage` (a string literal: kept by pointer) for its
// lifetime; nests (the innermost stage counts).
class FaultStage
{
public:
  explicit FaultStage(const char* stage);
  ~FaultStage();
  FaultStage(const FaultStage&) = delete;
  FaultStage& operator=(const FaultStage&) = delete;

private:
  const char* previous_;
};

namespace detail
{

extern std::atomic<bool> faultHooksActive; // an injection is armed or calls are counted

inline bool faultHooksOn()
{
  return faultHooksActive.load(std::memory_order_relaxed);
}

// Counts a call of `kind` on this thread's stage; true when it is the one to fail.
bool takeInjectedFault(CudaCall kind);

constexpr bool startsWith(const char* s, const char* prefix)
{
  for (; *prefix; ++s, ++prefix)
  {
    if (*s != *prefix)
    {
      return false;
    }
  }
  return true;
}

constexpr bool contains(const char* s, const char* part)
{
  for (; *s; ++s)
  {
    if (startsWith(s, part))
    {
      return true;
    }
  }
  return false;
}

// The kind of a checked expression, from its text (MCV_CUDA_TRY's #expr).
constexpr CudaCall classifyCudaCall(const char* expr)
{
  while (*expr == ' ' || *expr == ':')
  {
    ++expr;
  }
  if (startsWith(expr, "cudaMalloc"))
  {
    return CudaCall::Alloc;
  }
  if (startsWith(expr, "cudaMemcpy") || startsWith(expr, "cudaMemset"))
  {
    return CudaCall::Copy;
  }
  if (startsWith(expr, "cudaStreamSynchronize") || startsWith(expr, "cudaEventSynchronize") ||
    startsWith(expr, "cudaDeviceSynchronize"))
  {
    return CudaCall::Sync;
  }
  if (startsWith(expr, "cudaGetLastError") || startsWith(expr, "cudaPeekAtLastError") ||
    startsWith(expr, "cub::") || contains(expr, "aunch"))
  {
    return CudaCall::Launch;
  }
  return CudaCall::Other;
}

} // namespace detail
} // namespace cuda
} // namespace mcv
