// Reading a reduced-coordinates array of either precision: float32, or
// float16 stored as IEEE binary16 bits in an unsigned-short array (DimensionReduction's
// CoordinatePrecision Float16; VTK 9.2 has no half-float array). The suite reads any
// unsigned-short coordinate array as float16; other numeric types by their value.
// Header-only, like the other mcv*.h helpers; conversions from the core's HalfCoordinates.h.
#pragma once

#include "HalfCoordinates.h" // mcv core (Filters/Core/common)

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkType.h"
#include "vtkTypeUInt16Array.h"

#include <cstdint>
#include <vector>

namespace mcv
{
namespace vtkhelpers
{

// The binary16 values of a float16 coordinate array (contiguous), else null.
inline const std::uint16_t* halfCoordinates(vtkDataArray* array)
{
  if (!array || array->GetDataType() != VTK_UNSIGNED_SHORT || !array->HasStandardMemoryLayout())
  {
    return nullptr;
  }
  return static_cast<const std::uint16_t*>(array->GetVoidPointer(0));
}

// Component c of tuple t as a number (float16 decoded).
inline double coordinateComponent(vtkDataArray* array, vtkIdType t, int c)
{
  if (const std::uint16_t* h = halfCoordinates(array))
  {
    float x = 0;
    halvesToFloats(h + t * array->GetNumberOfComponents() + c, 1, &x);
    return x;
  }
  return array->GetComponent(t, c);
}

// Tuples [first, first + count) as float32 into out (count x components).
inline void coordinateTuples(vtkDataArray* array, vtkIdType first, vtkIdType count, float* out)
{
  const int components = array->GetNumberOfComponents();
  if (const std::uint16_t* h = halfCoordinates(array))
  {
    halvesToFloats(h + first * components, static_cast<std::size_t>(count) * components, out);
    return;
  }
  for (vtkIdType t = 0; t < count; ++t)
  {
    for (int c = 0; c < components; ++c)
    {
      out[t * components + c] = static_cast<float>(array->GetComponent(first + t, c));
    }
  }
}

// The whole array as float32: its own memory when it is a float array, else a converted
// copy in `storage` (float16 decoded). For readers that need every value as float at once;
// the transfer-function paths decode chunk by chunk instead (halfCoordinates).
inline const float* coordinatesAsFloats(vtkDataArray* array, std::vector<float>& storage)
{
  if (auto floats = vtkFloatArray::FastDownCast(array))
  {
    return floats->GetPointer(0);
  }
  const vtkIdType n = array->GetNumberOfTuples();
  storage.resize(static_cast<std::size_t>(n) * array->GetNumberOfComponents());
  coordinateTuples(array, 0, n, storage.data());
  return storage.data();
}

} // namespace vtkhelpers
} // namespace mcv
