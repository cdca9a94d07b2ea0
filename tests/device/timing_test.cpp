#include "device/seqlock.h"
#include "device/timing_histogram.h"
#include <gtest/gtest.h>
#include <atomic>
#include <thread>

using namespace hb;

TEST(TimingHistogramTest, PercentilesOfUniformSamples) {
  TimingHistogram h(1000, 10000);  // 1 us bins
  for (int i = 1; i <= 1000; ++i) h.add(i * 1000);  // 1..1000 us
  EXPECT_EQ(h.count(), 1000u);
  EXPECT_EQ(h.percentile_ns(0.5), 500000 + 1000);  // upper edge of the bin holding 500 us
  EXPECT_EQ(h.percentile_ns(0.99), 990000 + 1000);
  EXPECT_EQ(h.max_ns(), 1000000);
  EXPECT_EQ(h.count_above(899999), 101u);
}

TEST(TimingHistogramTest, OverflowIsCountedAndMaxIsExact) {
  TimingHistogram h(10, 10);  // up to 100 ns
  h.add(5);
  h.add(123456);
  EXPECT_EQ(h.count(), 2u);
  EXPECT_EQ(h.max_ns(), 123456);
  EXPECT_EQ(h.percentile_ns(1.0), 123456);
  h.clear();
  EXPECT_EQ(h.count(), 0u);
  EXPECT_EQ(h.percentile_ns(0.5), 0);
}

namespace {
struct Payload {
  std::uint64_t a, b, c, d, e;
};
} // namespace

TEST(SeqlockTest, ReaderNeverSeesATornValue) {
  Seqlock<Payload> lock(Payload{0, 0, 0, 0, 0});
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (std::uint64_t i = 1; i <= 200000; ++i) lock.store(Payload{i, i, i, i, i});
    done = true;
  });
  std::uint64_t reads = 0, last = 0;
  while (!done || reads == 0) {
    const Payload p = lock.load();
    ASSERT_EQ(p.a, p.b);
    ASSERT_EQ(p.a, p.c);
    ASSERT_EQ(p.a, p.e);
    ASSERT_GE(p.a, last);  // never goes back in time
    last = p.a;
    ++reads;
  }
  writer.join();
  EXPECT_EQ(lock.load().a, 200000u);
}
