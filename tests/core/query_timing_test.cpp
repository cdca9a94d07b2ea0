// Timing single queries (query_timing.h): the pooled tail and each probe's own tail.
#include "evaluation/query_timing.h"
#include <gtest/gtest.h>
#include <chrono>
#include <vector>

namespace hb {
namespace {

// A query that spins for a time chosen per probe and per call: probe 0 is slow on every
// call (a slow probe), probe 1 only on the first call (a one-off stall of the machine),
// every other probe fast.
class SpinningQuery final : public ContactQuery {
public:
  Contact query(const Segment& segment, const ForceLaw&) const noexcept override {
    const int probe = int(segment.start.x());
    const bool slow = probe == 0 || (probe == 1 && calls_of_probe1_++ == 0);
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(slow ? 200 : 1);
    while (std::chrono::steady_clock::now() < until) {
    }
    return Contact{};
  }

private:
  mutable int calls_of_probe1_ = 0;
};

std::vector<Segment> numbered_probes(int count) {
  std::vector<Segment> probes;
  for (int i = 0; i < count; ++i) probes.push_back({Vec3(float(i), 0.f, 0.f), Vec3(float(i), 1.f, 0.f)});
  return probes;
}

TEST(QueryTimingTest, EachProbesMedianKeepsASlowProbeAndDropsAOneOffStall) {
  const SpinningQuery query;
  const QueryLatency t = single_query_latency(query, numbered_probes(50), ForceLaw{}, 5);
  EXPECT_EQ(t.queries, 250u);
  // Pooled: both the slow probe (5 times) and the stall (once) are in the tail.
  EXPECT_GE(t.max_ns, 200e3);
  // Per probe: the slow probe stays the maximum, the stalled probe's median is fast, so the
  // second slowest probe is fast: p99 of 50 probes interpolates between the two slowest.
  EXPECT_GE(t.probe_max_ns, 200e3);
  EXPECT_LT(t.probe_p50_ns, 100e3);
  EXPECT_LE(t.probe_p50_ns, t.probe_p99_ns);
  EXPECT_LE(t.probe_p99_ns, t.probe_p999_ns);
  EXPECT_LE(t.probe_p999_ns, t.probe_max_ns);
}

TEST(QueryTimingTest, WithOneRoundEachProbesTimeIsItsOnlyTime) {
  const SpinningQuery query;
  const QueryLatency t = single_query_latency(query, numbered_probes(40), ForceLaw{}, 1);
  EXPECT_EQ(t.p50_ns, t.probe_p50_ns);
  EXPECT_EQ(t.p99_ns, t.probe_p99_ns);
  EXPECT_EQ(t.p999_ns, t.probe_p999_ns);
  EXPECT_EQ(t.max_ns, t.probe_max_ns);
}

} // namespace
} // namespace hb
