#include "parallel/thread_limit.h"
#include <tbb/global_control.h>
#include <algorithm>

namespace hb {

struct ThreadLimit::Control {
  tbb::global_control control;
  explicit Control(int threads) : control(tbb::global_control::max_allowed_parallelism, std::size_t(threads)) {}
};

ThreadLimit::ThreadLimit(int threads)
    : control_(std::make_unique<Control>(std::max(1, threads))), threads_(std::max(1, threads)) {}

ThreadLimit::~ThreadLimit() = default;

int ThreadLimit::current() {
  return int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

} // namespace hb
