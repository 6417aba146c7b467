// The few command-line options of the benchmark programs: "--name value" and "--flag".
#pragma once

#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace mcv
{
namespace testing
{

// The word after `name` on the command line, or `fallback`.
inline const char* optionText(int argc, char** argv, const char* name, const char* fallback)
{
  for (int i = 1; i + 1 < argc; ++i)
  {
    if (std::strcmp(argv[i], name) == 0)
    {
      return argv[i + 1];
    }
  }
  return fallback;
}

// The number after `name` on the command line, or `fallback`.
inline double optionNumber(int argc, char** argv, const char* name, double fallback)
{
  const char* text = optionText(argc, argv, name, nullptr);
  return text ? std::atof(text) : fallback;
}

// True when `name` is on the command line.
inline bool hasFlag(int argc, char** argv, const char* name)
{
  for (int i = 1; i < argc; ++i)
  {
    if (std::strcmp(argv[i], name) == 0)
    {
      return true;
    }
  }
  return false;
}

// The items of a comma-separated list ("cpu,gpu"); empty items are skipped.
inline std::vector<std::string> stringList(const std::string& text)
{
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');)
  {
    if (!item.empty())
    {
      out.push_back(item);
    }
  }
  return out;
}

// The integers of a comma-separated list ("64,128,256"); empty items are skipped.
inline std::vector<int> integerList(const char* text)
{
  std::vector<int> out;
  for (const std::string& item : stringList(text))
  {
    out.push_back(std::atoi(item.c_str()));
  }
  return out;
}

} // namespace testing
} // namespace mcv
