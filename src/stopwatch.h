#pragma once
// Wall-clock seconds since a steady_clock time point (bake and evaluation timings).
#include <chrono>

namespace hb {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace hb
