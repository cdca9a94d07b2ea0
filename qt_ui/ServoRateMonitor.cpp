#include "ServoRateMonitor.h"
#include <chrono>

hb::Contact ServoRateMonitor::query(const hb::Segment& segment, const hb::ForceLaw& law) const noexcept {
  const std::int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               std::chrono::steady_clock::now().time_since_epoch()).count();
  const std::int64_t last = last_ns_.exchange(now, std::memory_order_relaxed);
  if (last != 0 && now > last) {
    const std::int64_t p = now - last;
    std::size_t bin = static_cast<std::size_t>(p / kBinNs);
    if (bin >= kBins) bin = kBins - 1;
    bins_[bin].fetch_add(1, std::memory_order_relaxed);
    sum_ns_.fetch_add(p, std::memory_order_relaxed);
    count_.fetch_add(1, std::memory_order_release);
  }
  return scene_.query(segment, law);
}

ServoRateMonitor::Window ServoRateMonitor::takeWindow() noexcept {
  Window w;
  const std::uint64_t count = count_.load(std::memory_order_acquire);
  const std::int64_t sum = sum_ns_.load(std::memory_order_relaxed);
  std::array<std::uint64_t, kBins> delta{};
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < kBins; ++i) {
    const std::uint64_t b = bins_[i].load(std::memory_order_relaxed);
    delta[i] = b - seen_[i];
    seen_[i] = b;
    total += delta[i];
  }
  w.ticks = count - seen_count_;
  const std::int64_t dsum = sum - seen_sum_;
  seen_count_ = count;
  seen_sum_ = sum;
  if (w.ticks == 0 || total == 0 || dsum <= 0) return w;
  w.rate_hz = static_cast<double>(w.ticks) / (static_cast<double>(dsum) * 1e-9);
  const std::uint64_t rank = static_cast<std::uint64_t>(0.99 * static_cast<double>(total));
  std::uint64_t acc = 0;
  for (std::size_t i = 0; i < kBins; ++i) {
    acc += delta[i];
    if (acc > rank) {
      w.p99_period_us = static_cast<double>((i + 1) * kBinNs) * 1e-3;
      break;
    }
  }
  return w;
}
