#pragma once
// Fixed-bin latency histogram: allocated once at construction, add() is O(1), noexcept and
// allocation-free so the servo loop can record every tick.
#include <cstdint>
#include <vector>

namespace hb {

class TimingHistogram {
public:
  /// `bin_ns` > 0 is the bin width, `bins` > 0 the number of bins; samples past the last bin
  /// are counted in an overflow bin (their exact maximum is still tracked).
  TimingHistogram(std::uint32_t bin_ns, std::uint32_t bins);

  void add(std::int64_t ns) noexcept;
  void clear() noexcept;

  std::uint64_t count() const noexcept { return count_; }
  std::int64_t max_ns() const noexcept { return max_; }
  std::int64_t min_ns() const noexcept { return count_ ? min_ : 0; }
  double mean_ns() const noexcept { return count_ ? static_cast<double>(sum_) / count_ : 0.0; }
  /// Upper edge of the bin holding quantile q in [0, 1], ns (the max when in the overflow bin).
  std::int64_t percentile_ns(double q) const noexcept;
  /// Samples strictly above `ns` (at bin resolution).
  std::uint64_t count_above(std::int64_t ns) const noexcept;

private:
  std::uint32_t bin_ns_;
  std::vector<std::uint64_t> bins_;
  std::uint64_t overflow_ = 0;
  std::uint64_t count_ = 0;
  std::int64_t sum_ = 0;
  std::int64_t max_ = 0;
  std::int64_t min_ = 0;
};

} // namespace hb
