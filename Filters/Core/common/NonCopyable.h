// A base for classes that own device memory, streams or pinned buffers through raw handles
// released in their destructor: a copy would release them twice, so copying and assigning
// are deleted once here instead of in every such class.
#pragma once

namespace mcv
{

class NonCopyable
{
public:
  NonCopyable(const NonCopyable&) = delete;
  NonCopyable& operator=(const NonCopyable&) = delete;

protected:
  NonCopyable() = default;
  ~NonCopyable() = default;
};

} // namespace mcv
