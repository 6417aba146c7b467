#include "FaultInjection.h"

#include "EnumNames.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <utility>

namespace mcv
{
namespace cuda
{

namespace detail
{
std::atomic<bool> faultHooksActive{ false };

static_assert(classifyCudaCall("cudaMalloc(&p, n)") == CudaCall::Alloc, "");
static_assert(classifyCudaCall("cudaMallocHost(&p, n)") == CudaCall::Alloc, "");
static_assert(classifyCudaCall("cudaMemcpyAsync(d, s, n, k, st)") == CudaCall::Copy, "");
static_assert(classifyCudaCall("cudaMemsetAsync(d, 0, n, st)") == CudaCall::Copy, "");
static_assert(classifyCudaCall("cudaMemcpyToSymbol(c, s, n)") == CudaCall::Copy, "");
static_assert(classifyCudaCall("cudaGetLastError()") == CudaCall::Launch, "");
static_assert(classifyCudaCall("cub::DeviceSelect::If(t, b, f, o, c, n, op, st)") == CudaCall::Launch, "");
static_assert(classifyCudaCall("launchError") == CudaCall::Launch, "");
static_assert(classifyCudaCall("cudaStreamSynchronize(stream)") == CudaCall::Sync, "");
static_assert(classifyCudaCall("cudaEventRecord(e, stream)") == CudaCall::Other, "");
} // namespace detail

namespace
{

const char* const kStages[] = { "harris", "features", "gaussiantf", "outofsample", "umaplayout", "fused", "fusedpasses", "samplekeys", "isomapfit" };

struct InjectionState
{
  std::mutex mutex;
  bool armed = false;
  std::string stage;
  CudaCall kind = CudaCall::Alloc;
  long n = 0, seen = 0;
  bool counting = false;
  std::map<std::pair<std::string, int>, long> counts;
  long fired = 0;

  // Under the mutex.
  void updateActive()
  {
    detail::faultHooksActive.store(armed || counting, std::memory_order_relaxed);
  }
};

InjectionState& state()
{
  static InjectionState* s = new InjectionState; // never destroyed: used until exit
  return *s;
}

thread_local const char* currentStage = nullptr;

bool knownStage(const std::string& stage)
{
  for (const char* s : kStages)
  {
    if (stage == s)
    {
      return true;
    }
  }
  return false;
}

const EnumName<CudaCall> kCallNames[] = { { CudaCall::Any, "any" }, { CudaCall::Alloc, "alloc" },
  { CudaCall::Copy, "copy" }, { CudaCall::Launch, "launch" }, { CudaCall::Sync, "sync" },
  { CudaCall::Other, "other" } };

bool parseKind(const std::string& text, CudaCall& kind)
{
  return valueOf(kCallNames, text, kind);
}

// Parses "<stage>:<n>" or "<stage>:<kind>:<n>".
bool parseSpec(const std::string& spec, std::string& stage, CudaCall& kind, long& n, std::string* error)
{
  auto fail = [&](const std::string& why) {
    if (error)
    {
      *error = why;
    }
    return false;
  };
  const std::string usage = "expected <stage>:<n> or <stage>:<kind>:<n> with stage harris, "
                            "features, gaussiantf, outofsample, umaplayout, fused, fusedpasses or samplekeys, kind any, alloc, copy, launch, "
                            "sync or other, n >= 1";
  const auto first = spec.find(':'), last = spec.rfind(':');
  if (first == std::string::npos)
  {
    return fail(usage);
  }
  stage = spec.substr(0, first);
  if (!knownStage(stage))
  {
    return fail("unknown stage '" + stage + "'; " + usage);
  }
  kind = CudaCall::Alloc;
  if (last != first && !parseKind(spec.substr(first + 1, last - first - 1), kind))
  {
    return fail("unknown kind of call; " + usage);
  }
  const std::string count = spec.substr(last + 1);
  char* end = nullptr;
  n = std::strtol(count.c_str(), &end, 10);
  if (count.empty() || *end != '\0' || n < 1)
  {
    return fail("bad call number '" + count + "'; " + usage);
  }
  return true;
}

void arm(const std::string& stage, CudaCall kind, long n)
{
  InjectionState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  s.armed = n > 0;
  s.stage = stage;
  s.kind = kind;
  s.n = n;
  s.seen = 0;
  s.updateActive();
}

// MCV_CUDA_FAIL_AT, once, before the first stage or API call (which then overrides it).
void readEnvironmentOnce()
{
  static std::once_flag once;
  std::call_once(once, [] {
    const char* spec = std::getenv("MCV_CUDA_FAIL_AT");
    if (!spec || !*spec)
    {
      return;
    }
    std::string stage, error;
    CudaCall kind = CudaCall::Alloc;
    long n = 0;
    if (parseSpec(spec, stage, kind, n, &error))
    {
      arm(stage, kind, n);
    }
    else
    {
      std::fprintf(stderr, "MCV_CUDA_FAIL_AT=%s ignored: %s\n", spec, error.c_str());
    }
  });
}

} // namespace

const char* cudaCallName(CudaCall kind)
{
  return nameOf(kCallNames, kind, "?");
}

void injectFailure(const std::string& stage, CudaCall kind, long n)
{
  readEnvironmentOnce();
  arm(stage, kind, n);
}

bool injectFailure(const std::string& spec, std::string* error)
{
  readEnvironmentOnce();
  std::string stage;
  CudaCall kind = CudaCall::Alloc;
  long n = 0;
  if (!parseSpec(spec, stage, kind, n, error))
  {
    return false;
  }
  arm(stage, kind, n);
  return true;
}

void clearInjectedFailure()
{
  readEnvironmentOnce();
  InjectionState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  s.armed = false;
  s.updateActive();
}

bool failurePending()
{
  readEnvironmentOnce();
  InjectionState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  return s.armed;
}

long injectedFailureCount()
{
  readEnvironmentOnce();
  InjectionState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  return s.fired;
}

void countCudaCalls(bool on)
{
  readEnvironmentOnce();
  InjectionState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  s.counting = on;
  if (on)
  {
    s.counts.clear();
  }
  s.updateActive();
}

long countedCudaCalls(const std::string& stage, CudaCall kind)
{
  InjectionState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  const auto it = s.counts.find({ stage, static_cast<int>(kind) });
  return it == s.counts.end() ? 0 : it->second;
}

FaultStage::FaultStage(const char* stage)
  : previous_(currentStage)
{
  readEnvironmentOnce();
  currentStage = stage;
}

FaultStage::~FaultStage()
{
  currentStage = previous_;
}

namespace detail
{

bool takeInjectedFault(CudaCall kind)
{
  const char* stage = currentStage;
  if (!stage)
  {
    return false;
  }
  InjectionState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  if (s.counting)
  {
    ++s.counts[{ stage, static_cast<int>(kind) }];
    ++s.counts[{ stage, static_cast<int>(CudaCall::Any) }];
  }
  if (!s.armed || s.stage != stage || (s.kind != CudaCall::Any && s.kind != kind) ||
    ++s.seen < s.n)
  {
    return false;
  }
  s.armed = false;
  ++s.fired;
  s.updateActive();
  return true;
}

} // namespace detail

} // namespace cuda
} // namespace mcv
