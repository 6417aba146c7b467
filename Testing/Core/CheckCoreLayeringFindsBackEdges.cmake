# cmake -DCORE=<Filters/Core> -DCHECK=<CheckCoreLayering.cmake> -DWORK=<scratch folder> -P ...
# The layering check itself: it passes on a copy of the core, and fails, naming the file and
# the header, on that copy with one back edge put in at a time: GPU code of the reduction
# including the features' fused placement (features sits above reduction), common GPU
# plumbing including the viewpoint's kernel header, common CPU code including a
# capability's GPU header (the edge Device.cpp once had), and a relative path up.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(COPY ${CORE}/ DESTINATION ${WORK}/Core)

function(run_check result output)
  execute_process(COMMAND ${CMAKE_COMMAND} -DCORE=${WORK}/Core -P ${CHECK}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${result} ${rc} PARENT_SCOPE)
  set(${output} "${out}${err}" PARENT_SCOPE)
endfunction()

run_check(rc text)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the check fails on an unchanged copy of the core:\n${text}")
endif()

# file (relative to the core), the line put in, what the check must say.
set(cases
  "reduction/cuda/OutOfSampleCuda.cu|#include \"cuda/FusedPlacementCuda.h\"|reduction/cuda/OutOfSampleCuda.cu: cuda/FusedPlacementCuda.h is features/cuda/FusedPlacementCuda.h"
  "common/cuda/DeviceBuffer.cuh|#include \"cuda/HarrisKernel.cuh\"|common/cuda/DeviceBuffer.cuh: cuda/HarrisKernel.cuh is viewpoint/cuda/HarrisKernel.cuh"
  "common/Device.cpp|#include \"cuda/HarrisCuda.h\"|common/Device.cpp: cuda/HarrisCuda.h is viewpoint/cuda/HarrisCuda.h"
  "viewpoint/cuda/HarrisCuda.cu|#include \"../../reduction/OutOfSample.h\"|viewpoint/cuda/HarrisCuda.cu: ../../reduction/OutOfSample.h \\(a relative path up")
foreach(case IN LISTS cases)
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 target)
  list(GET parts 1 line)
  list(GET parts 2 expected)
  set(path ${WORK}/Core/${target})
  if(NOT EXISTS ${path})
    message(FATAL_ERROR "no ${target} in the core to put a back edge in")
  endif()
  file(READ ${path} original)
  file(WRITE ${path} "${line}\n${original}")
  run_check(rc text)
  file(WRITE ${path} "${original}")
  if(rc EQUAL 0)
    message(FATAL_ERROR "the check passed with ${line} in ${target}")
  endif()
  if(NOT text MATCHES "${expected}")
    message(FATAL_ERROR "the check failed with ${line} in ${target}, but did not say '${expected}':\n${text}")
  endif()
  message(STATUS "found: ${line} in ${target}")
endforeach()
file(REMOVE_RECURSE ${WORK})
