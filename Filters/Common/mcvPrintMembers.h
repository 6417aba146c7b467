// The members a filter's PrintSelf prints, one line "<indent><Name>: <value>" each, named
// once: the macro takes the members themselves and prints each under its own name.
//
//   mcvPrintMembersMacro(os, indent, this->SampleSize, this->RandomSeed);
//
// prints "SampleSize: 10000" and "RandomSeed: 0". Fixed-size arrays print their values
// separated by spaces; a null string prints "(none)". Header-only, like mcvChannelArrays.h.
#pragma once

#include "vtkIndent.h"

#include <cstddef> // for std::size_t
#include <ostream> // for std::ostream
#include <string>  // for std::string

namespace mcv
{
namespace vtkhelpers
{

template <class T>
void printMemberValue(std::ostream& os, const T& value)
{
  os << value;
}

inline void printMemberValue(std::ostream& os, const char* value)
{
  os << (value ? value : "(none)");
}

inline void printMemberValue(std::ostream& os, char* value)
{
  printMemberValue(os, static_cast<const char*>(value));
}

template <class T, std::size_t N>
void printMemberValue(std::ostream& os, const T (&values)[N])
{
  for (std::size_t i = 0; i < N; ++i)
  {
    os << (i ? " " : "") << values[i];
  }
}

// One line per value. `names` is the comma-separated list of the values as written
// ("this->A, this->B"), each printed without its "this->".
template <class... T>
void printMembers(std::ostream& os, vtkIndent indent, const char* names, const T&... values)
{
  std::string list(names);
  std::size_t start = 0;
  auto printOne = [&](const auto& value) {
    std::size_t end = list.find(',', start);
    end = end == std::string::npos ? list.size() : end;
    std::string name = list.substr(start, end - start);
    start = end + 1;
    name.erase(0, name.find_first_not_of(" \t\n"));
    name.erase(name.find_last_not_of(" \t\n") + 1);
    if (name.compare(0, 6, "this->") == 0)
    {
      name.erase(0, 6);
    }
    os << indent << name << ": ";
    printMemberValue(os, value);
    os << "\n";
  };
  (printOne(values), ...);
}

} // namespace vtkhelpers
} // namespace mcv

#define mcvPrintMembersMacro(os, indent, ...)                                                     \
  mcv::vtkhelpers::printMembers(os, indent, #__VA_ARGS__, __VA_ARGS__)
