#pragma once
// Live servo timing for the readout: the period between the servo thread's queries.
#include "haptic_box/contact.h"
#include <array>
#include <atomic>
#include <cstdint>

/// Decorates the scene the servo loop queries: forwards every query and records, on the servo
/// thread, the time since the previous query in a fixed-bin histogram of atomics (no
/// allocation, no lock). ServoLoop's own histograms are read only after stop(); this one can be
/// read at display rate. The servo loop queries once per tick, so query-to-query time is the
/// tick period (plus the device read's jitter).
class ServoRateMonitor final : public hb::ContactQuery {
public:
  static constexpr std::uint32_t kBinNs = 10000;   ///< 10 us bins
  static constexpr std::size_t kBins = 2000;       ///< up to 20 ms; the last bin is overflow

  explicit ServoRateMonitor(const hb::ContactQuery& scene) noexcept : scene_(scene) {}
  hb::Contact query(const hb::Segment& segment, const hb::ForceLaw& law) const noexcept override;

  /// Rate and p99 period over the ticks since the previous call (GUI thread, one reader).
  struct Window {
    double rate_hz = 0.0;
    double p99_period_us = 0.0;
    std::uint64_t ticks = 0;
  };
  Window takeWindow() noexcept;

private:
  const hb::ContactQuery& scene_;
  mutable std::atomic<std::int64_t> last_ns_{0};
  mutable std::array<std::atomic<std::uint64_t>, kBins> bins_{};
  mutable std::atomic<std::uint64_t> count_{0};
  mutable std::atomic<std::int64_t> sum_ns_{0};
  // Reader side: the cumulative figures at the previous takeWindow().
  std::array<std::uint64_t, kBins> seen_{};
  std::uint64_t seen_count_ = 0;
  std::int64_t seen_sum_ = 0;
};
