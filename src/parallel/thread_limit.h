#pragma once
// How many threads the core's parallel loops (TBB) may use in this process, for as long as a
// ThreadLimit lives. Used to give each MPI rank its share of a node's cores, and to compare
// ranks against threads on one machine.
#include <memory>

namespace hb {

/// While alive, TBB's parallel loops in this process use at most `threads` threads (>= 1).
class ThreadLimit {
public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

  int threads() const { return threads_; }
  /// The threads TBB would use now (the active limit, else the machine's cores).
  static int current();

private:
  struct Control;
  std::unique_ptr<Control> control_;
  int threads_;
};

} // namespace hb
