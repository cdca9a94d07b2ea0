#include "device/timing_histogram.h"
#include <algorithm>
#include <cmath>

namespace hb {

TimingHistogram::TimingHistogram(std::uint32_t bin_ns, std::uint32_t bins)
    : bin_ns_(std::max<std::uint32_t>(1, bin_ns)), bins_(std::max<std::uint32_t>(1, bins), 0) {}

void TimingHistogram::add(std::int64_t ns) noexcept {
  if (ns < 0) ns = 0;
  const std::uint64_t b = static_cast<std::uint64_t>(ns) / bin_ns_;
  if (b < bins_.size()) ++bins_[b];
  else ++overflow_;
  if (count_ == 0 || ns < min_) min_ = ns;
  if (ns > max_) max_ = ns;
  sum_ += ns;
  ++count_;
}

void TimingHistogram::clear() noexcept {
  std::fill(bins_.begin(), bins_.end(), 0);
  overflow_ = count_ = 0;
  sum_ = max_ = min_ = 0;
}

std::int64_t TimingHistogram::percentile_ns(double q) const noexcept {
  if (count_ == 0) return 0;
  q = std::clamp(q, 0.0, 1.0);
  const auto rank = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_)));
  const std::uint64_t target = std::max<std::uint64_t>(1, rank);
  std::uint64_t acc = 0;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    acc += bins_[i];
    if (acc >= target)
      return std::min<std::int64_t>(max_, static_cast<std::int64_t>((i + 1) * bin_ns_));
  }
  return max_;
}

std::uint64_t TimingHistogram::count_above(std::int64_t ns) const noexcept {
  if (ns < 0) return count_;
  const std::uint64_t first = static_cast<std::uint64_t>(ns) / bin_ns_ + 1;
  std::uint64_t n = overflow_;
  for (std::size_t i = first; i < bins_.size(); ++i) n += bins_[i];
  return n;
}

} // namespace hb
