// A 4-ary min-heap of items 0..n-1 with their keys, with decrease-key.
//
// Why by hand: std::priority_queue has no decrease-key, so Dijkstra with it pushes a
// stale copy per improvement and spent half of Isomap's fit sifting them (perf, 10000
// points); Boost's d_ary_heap_indirect would pull in Boost.Graph's property maps for
// sixty lines. Four children per node halve the depth; keys stored beside their items keep
// the comparisons of a sift in one or two cache lines.
#pragma once

#include <cstdint>
#include <vector>

namespace mcv
{

class IndexedMinHeap
{
public:
  static constexpr std::uint32_t kAbsent = 0xffffffffu;

  // Empties the heap for items 0..n-1.
  void reset(std::size_t n)
  {
    heap_.clear();
    position_.assign(n, kAbsent);
  }
  bool empty() const { return heap_.empty(); }

  // Inserts item with key, or moves it up to its new, smaller key.
  void pushOrDecrease(std::uint32_t item, double key)
  {
    std::uint32_t at = position_[item];
    if (at == kAbsent)
    {
      at = static_cast<std::uint32_t>(heap_.size());
      heap_.push_back({ key, item });
    }
    siftUp(at, { key, item });
  }

  std::uint32_t popMin()
  {
    const std::uint32_t top = heap_.front().item;
    position_[top] = kAbsent;
    const Entry last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty())
    {
      siftDown(0, last);
    }
    return top;
  }

private:
  struct Entry
  {
    double key;
    std::uint32_t item;
  };
  void place(std::uint32_t at, const Entry& entry)
  {
    heap_[at] = entry;
    position_[entry.item] = at;
  }
  void siftUp(std::uint32_t at, const Entry& entry)
  {
    while (at > 0)
    {
      const std::uint32_t parent = (at - 1) / 4;
      if (!(entry.key < heap_[parent].key))
      {
        break;
      }
      place(at, heap_[parent]);
      at = parent;
    }
    place(at, entry);
  }
  void siftDown(std::uint32_t at, const Entry& entry)
  {
    const std::size_t size = heap_.size();
    for (;;)
    {
      const std::size_t first = 4 * static_cast<std::size_t>(at) + 1;
      if (first >= size)
      {
        break;
      }
      std::size_t best = first;
      const std::size_t end = first + 4 < size ? first + 4 : size;
      for (std::size_t c = first + 1; c < end; ++c)
      {
        if (heap_[c].key < heap_[best].key)
        {
          best = c;
        }
      }
      if (!(heap_[best].key < entry.key))
      {
        break;
      }
      place(at, heap_[best]);
      at = static_cast<std::uint32_t>(best);
    }
    place(at, entry);
  }

  std::vector<Entry> heap_;
  std::vector<std::uint32_t> position_;
};

} // namespace mcv
