#pragma once
// What the servo-loop tests share: options for a loaded shared machine and a bounded wait.
#include "device/servo_loop.h"
#include <chrono>
#include <thread>

namespace hb::test {

/// No real-time request (the tests share the machine with builds), a watchdog that never fires
/// (timing is measured by `hapticbox servo`, not asserted), a 10 ms ramp, a model in mm with a
/// 10 mm probe and k = 1000 N/m.
inline ServoOptions servo_test_options() {
  ServoOptions o;
  o.request_realtime = false;
  o.safety.watchdog_bound_s = 10.0;
  o.safety.ramp_seconds = 0.01f;
  o.workspace.metres_per_unit = 1e-3;
  o.workspace.probe_length = 10.f;
  o.workspace.stiffness_n_per_m = 1000.0;
  return o;
}

/// Waits until the loop has run `n` ticks or stopped, at most about `max_ms` milliseconds.
inline void wait_ticks(const ServoLoop& loop, std::uint64_t n, int max_ms = 2000) {
  for (int i = 0; i < max_ms && loop.snapshot().tick < n && loop.running(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

} // namespace hb::test
