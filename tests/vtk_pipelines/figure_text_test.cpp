// Figures as printed by the CLI, the report and the window: significant digits, not raw precision.
#include "figure_text.h"
#include <gtest/gtest.h>
#include <cmath>

TEST(FigureTextTest, SignificantDigitsDropTrailingZerosAndGroupThousands) {
  EXPECT_EQ(hb::sig(0.0015234), "0.00152");
  EXPECT_EQ(hb::sig(150.995), "151");
  EXPECT_EQ(hb::sig(15011.68), "15,000");
  EXPECT_EQ(hb::sig(0.11), "0.11");
  EXPECT_EQ(hb::sig(2.0), "2");
  EXPECT_EQ(hb::sig(0.0), "0");
  EXPECT_EQ(hb::sig(-3.14159), "-3.14");
  EXPECT_EQ(hb::sig(999.7), "1000");  // separators from 10,000 up
  EXPECT_EQ(hb::sig(123456.0), "123,000");
  EXPECT_EQ(hb::sig(std::nan("")), "n/a");
}

TEST(FigureTextTest, PercentKeepsSmallErrorsVisible) {
  EXPECT_EQ(hb::percent(0.000015), "0.0015 %");
  EXPECT_EQ(hb::percent(150.1168), "15,000 %");
  EXPECT_EQ(hb::agreement_percent(0.99515), "99.52 %");
  EXPECT_EQ(hb::agreement_percent(0.9), "90 %");
  EXPECT_EQ(hb::agreement_percent(1.0), "100 %");
  EXPECT_EQ(hb::agreement_percent(0.99999), "99.999 %");
}

TEST(FigureTextTest, BytesCountsAndDurationsReadAsPeopleWriteThem) {
  EXPECT_EQ(hb::bytes_text(150995000), "151 MB");
  EXPECT_EQ(hb::bytes_text(3300), "3.3 kB");
  EXPECT_EQ(hb::bytes_text(512), "512 B");
  EXPECT_EQ(hb::count_text(18874368), "18.9 M");
  EXPECT_EQ(hb::count_text(5000), "5000");
  EXPECT_EQ(hb::count_text(52000), "52 k");
  EXPECT_EQ(hb::duration_text(1.6), "1.6 s");
  EXPECT_EQ(hb::duration_text(0.00045), "450 us");
  EXPECT_EQ(hb::duration_text(3.1e-7), "310 ns");
}

TEST(FigureTextTest, SpeedVerdictSaysFasterOrSlowerAndByHowMuch) {
  EXPECT_EQ(hb::speed_verdict(3.72e-6, 0.4e-6), "9.3x slower than exact");
  EXPECT_EQ(hb::speed_verdict(56e-9, 1060e-9), "19x faster than exact");
  EXPECT_EQ(hb::speed_verdict(1.0, 1.02), "as fast as exact (1x)");
  EXPECT_EQ(hb::speed_verdict(0.0, 1.0), "not measured");
  EXPECT_EQ(hb::compare_speed(1.0, 1.02), hb::SpeedComparison::as_fast);
  EXPECT_EQ(hb::compare_speed(56e-9, 1060e-9), hb::SpeedComparison::faster);
}
