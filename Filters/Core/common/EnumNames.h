// The names of an enum's values, both ways: each enum that is written into messages, files
// or environment variables keeps one table of {value, name} rows, which serves the name of
// a value and the value of a name alike.
#pragma once

#include <cstddef>
#include <string>

namespace mcv
{

template <class Enum>
struct EnumName
{
  Enum value;
  const char* name;
};

// The name of `value` in `names`; `unknown` when no row has it.
template <class Enum, std::size_t N>
const char* nameOf(const EnumName<Enum> (&names)[N], Enum value, const char* unknown)
{
  for (const EnumName<Enum>& row : names)
  {
    if (row.value == value)
    {
      return row.name;
    }
  }
  return unknown;
}

// The value named `name` in `names` into `value`; false (and `value` untouched) when no
// row has that name.
template <class Enum, std::size_t N>
bool valueOf(const EnumName<Enum> (&names)[N], const std::string& name, Enum& value)
{
  for (const EnumName<Enum>& row : names)
  {
    if (name == row.name)
    {
      value = row.value;
      return true;
    }
  }
  return false;
}

} // namespace mcv
