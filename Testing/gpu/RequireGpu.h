// GPU tests skip (not fail) where no CUDA device is usable, e.g. on CI machines.
#pragma once

#include "cuda/DeviceProbe.h"

#include <gtest/gtest.h>

#include <string>

#define MCV_REQUIRE_GPU()                                                                         \
  do                                                                                              \
  {                                                                                               \
    std::string why_;                                                                             \
    if (!mcv::cuda::deviceUsable(&why_))                                                          \
    {                                                                                             \
      GTEST_SKIP() << "no usable GPU: " << why_;                                                  \
    }                                                                                             \
  } while (0)
