// mcv::Communicator over threads of one process, for the core tests: R threads play R
// ranks, so "the same answer as one process" is checked without MPI. Each collective is a
// barrier: every rank posts its contribution, the last one to arrive combines them, all
// read the result.
#pragma once

#include "Communicator.h"

#include <algorithm>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace mcv
{
namespace testing
{

class ThreadGroup
{
public:
  explicit ThreadGroup(int ranks)
    : ranks_(ranks)
    , posted_(static_cast<std::size_t>(ranks))
  {
  }

  // Runs body(rank, communicator) on `ranks` threads and waits for all of them.
  void run(const std::function<void(int, const Communicator&)>& body);

  int ranks() const { return ranks_; }

  // One collective: `combine` turns the posted contributions (rank order) into the result.
  std::vector<char> exchange(int rank, const std::vector<char>& mine,
    const std::function<std::vector<char>(const std::vector<std::vector<char>>&)>& combine)
  {
    std::unique_lock<std::mutex> lock(mutex_);
    const unsigned long generation = generation_;
    posted_[static_cast<std::size_t>(rank)] = mine;
    if (++arrived_ == ranks_)
    {
      result_ = combine(posted_);
      arrived_ = 0;
      ++generation_;
      changed_.notify_all();
    }
    else
    {
      changed_.wait(lock, [&] { return generation_ != generation; });
    }
    return result_;
  }

private:
  int ranks_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::vector<char>> posted_;
  std::vector<char> result_;
  int arrived_ = 0;
  unsigned long generation_ = 0;
};

class ThreadCommunicator : public Communicator
{
public:
  ThreadCommunicator(ThreadGroup& group, int rank)
    : group_(group)
    , rank_(rank)
  {
  }
  int size() const override { return group_.ranks(); }
  int rank() const override { return rank_; }
  void sum(std::vector<double>& v) const override
  {
    reduce(v, [](double a, double b) { return a + b; });
  }
  void min(std::vector<double>& v) const override
  {
    reduce(v, [](double a, double b) { return std::min(a, b); });
  }
  void max(std::vector<double>& v) const override
  {
    reduce(v, [](double a, double b) { return std::max(a, b); });
  }
  std::vector<char> allGather(const std::vector<char>& local) const override
  {
    return group_.exchange(rank_, local, [](const std::vector<std::vector<char>>& all) {
      std::vector<char> out;
      for (const auto& part : all)
      {
        out.insert(out.end(), part.begin(), part.end());
      }
      return out;
    });
  }

private:
  void reduce(std::vector<double>& v, double (*op)(double, double)) const
  {
    const std::vector<double> all = allGatherValues(*this, v);
    const std::size_t n = v.size();
    for (std::size_t i = 0; i < n; ++i)
    {
      double acc = all[i];
      for (int r = 1; r < group_.ranks(); ++r)
      {
        acc = op(acc, all[static_cast<std::size_t>(r) * n + i]);
      }
      v[i] = acc;
    }
  }

  ThreadGroup& group_;
  int rank_;
};

inline void ThreadGroup::run(const std::function<void(int, const Communicator&)>& body)
{
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks_; ++r)
  {
    threads.emplace_back([this, r, &body] {
      ThreadCommunicator comm(*this, r);
      body(r, comm);
    });
  }
  for (std::thread& t : threads)
  {
    t.join();
  }
}

} // namespace testing
} // namespace mcv
