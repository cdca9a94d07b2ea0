// `servo BOX --exact MESH`: a second answer computed in shadow on every tick's segment, compared
// with the driving one and logged beside it, never sent to the device.
#include "analytic_scene.h"
#include "servo_test_support.h"
#include "device/servo_log.h"
#include "device/servo_loop.h"
#include "device/virtual_device.h"
#include "errors.h"
#include <gtest/gtest.h>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>

using namespace hb;
using namespace std::chrono_literals;

namespace {

ServoOptions shadow_test_options() { return test::servo_test_options(); }
void wait_shadow_ticks(const ServoLoop& loop, std::uint64_t n) { test::wait_ticks(loop, n, 3000); }

std::string shadow_temp(const char* name) { return ::testing::TempDir() + name; }

// Runs `drive` with `shadow` for about `ticks` ticks with the tip 2 mm below the plane z = 0.
ServoReport run_pressed(const ContactQuery& drive, const ContactQuery* shadow, std::uint64_t ticks,
                        LogRecorder* recorder = nullptr, ServoSnapshot* last = nullptr, Vec3* sent = nullptr) {
  VirtualDevice dev;
  dev.set_target(Vec3(0.f, 0.f, -0.002f));
  ServoLoop loop(dev, drive, shadow_test_options());
  loop.set_shadow(shadow);
  loop.set_recorder(recorder);
  loop.start();
  wait_shadow_ticks(loop, ticks);
  if (last) *last = loop.snapshot();
  if (sent) *sent = dev.last_force();
  loop.stop();
  return loop.report();
}

} // namespace

TEST(ServoShadowTest, ShadowAnswerNeverReachesTheDevice) {
  test::HalfSpaceScene plane(0.f);
  test::NanScene nan;  // a shadow answering NaN must change nothing the device gets
  ServoSnapshot s;
  Vec3 sent;
  const ServoReport r = run_pressed(plane, &nan, 100, nullptr, &s, &sent);
  EXPECT_TRUE(r.shadow.enabled);
  EXPECT_EQ(r.safety[static_cast<std::size_t>(SafetyEvent::non_finite)], 0u);
  EXPECT_EQ(s.contact, 1);
  EXPECT_EQ(s.shadow_contact, 1);
  EXPECT_TRUE(std::isnan(s.shadow_force_n[2]));
  EXPECT_NEAR(s.desired_force_n[2], 2.f, 1e-3f);  // 1000 N/m * 2 mm, from the driving plane
  EXPECT_TRUE(sent.allFinite());
  EXPECT_GT(sent.z(), 0.f);
  EXPECT_LE(sent.z(), 2.f + 1e-5f);
  EXPECT_EQ(r.shadow.shadow_only + r.shadow.drive_only, 0u);
}

TEST(ServoShadowTest, IdenticalShadowAgreesOnEveryTick) {
  test::HalfSpaceScene plane(0.f), same(0.f);
  const ServoReport r = run_pressed(plane, &same, 100);
  EXPECT_GE(r.shadow.both_contact, 100u);
  EXPECT_EQ(r.shadow.drive_only, 0u);
  EXPECT_EQ(r.shadow.shadow_only, 0u);
  EXPECT_EQ(r.shadow.force_diff_max_n, 0.0);
  EXPECT_EQ(r.shadow.angle_max_deg, 0.0);
  EXPECT_EQ(r.shadow.query.count, r.query.count);
}

TEST(ServoShadowTest, ShiftedShadowMeasuresTheForceDifference) {
  test::HalfSpaceScene plane(0.f), lower(-1.f);  // the shadow's surface 1 mm lower: 1 N less at 1000 N/m
  const ServoReport r = run_pressed(plane, &lower, 200);
  EXPECT_GE(r.shadow.both_contact, 100u);
  EXPECT_NEAR(r.shadow.force_diff_p50_n, 1.0, 2e-4);
  EXPECT_NEAR(r.shadow.force_diff_p99_n, 1.0, 2e-4);
  EXPECT_LE(r.shadow.angle_p99_deg, 0.01);
  // Without a shadow there is no comparison.
  const ServoReport alone = run_pressed(plane, nullptr, 20);
  EXPECT_FALSE(alone.shadow.enabled);
  EXPECT_EQ(alone.shadow.both_contact + alone.shadow.neither, 0u);
}

TEST(ServoShadowTest, ComparisonLogHoldsBothAnswersAndReplays) {
  const std::string path = shadow_temp("hb_shadow.hblog");
  test::HalfSpaceScene plane(0.f), lower(-1.f);
  {
    LogRecorder rec(path, 1000.0, VirtualDevice().spec(), RenderedAnswer::exact);
    run_pressed(plane, &lower, 150, &rec);
    rec.finish();
    EXPECT_EQ(rec.dropped(), 0u);
  }
  const ServoLog log = read_servo_log(path);
  ASSERT_TRUE(log.comparison);
  EXPECT_EQ(log.rendered, RenderedAnswer::exact);
  ASSERT_GE(log.records.size(), 150u);
  ASSERT_EQ(log.shadow.size(), log.records.size());
  const LogRecord& last = log.records.back();
  const ShadowRecord& s = log.shadow.back();
  EXPECT_EQ(last.contact, 1);
  EXPECT_NEAR(s.drive_force_n[2], 2.f, 1e-3f);
  EXPECT_NEAR(s.shadow_force_n[2], 1.f, 1e-3f);
  EXPECT_NEAR(s.shadow_depth, 1.f, 1e-3f);
  EXPECT_EQ(s.shadow_contact, 1);
  EXPECT_NEAR(s.drive_normal[2], 1.f, 1e-6f);
  EXPECT_LE(last.force_n[2], s.drive_force_n[2] + 1e-5f);  // the sent force is the driver's, after safety

  // The same log replays like a plain one.
  ReplayDevice replay(path);
  ServoLoop loop(replay, plane, shadow_test_options());
  loop.start();
  for (int i = 0; i < 3000 && loop.running(); ++i) std::this_thread::sleep_for(1ms);
  loop.stop();
  EXPECT_EQ(loop.report().exit, ServoExit::end_of_stream);
  EXPECT_EQ(loop.report().ticks, log.records.size());

  // CSV: box_* and exact_* columns; with the exact answer rendered, exact_* is the driver.
  const std::string csv = shadow_temp("hb_shadow.csv");
  write_servo_log_csv(log, csv);
  std::ifstream in(csv);
  std::string header, row, lastrow;
  std::getline(in, header);
  EXPECT_NE(header.find(",rendered,box_fx_n,"), std::string::npos) << header;
  EXPECT_NE(header.find(",exact_fz_n,"), std::string::npos) << header;
  std::size_t rows = 0;
  while (std::getline(in, row)) lastrow = row, ++rows;
  EXPECT_EQ(rows, log.records.size());
  std::vector<std::string> names, cells;
  for (std::stringstream h(header); std::getline(h, row, ',');) names.push_back(row);
  for (std::stringstream c(lastrow); std::getline(c, row, ',');) cells.push_back(row);
  ASSERT_EQ(names.size(), cells.size());
  const auto cell = [&](const std::string& name) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return cells[i];
    return std::string("missing ") + name;
  };
  EXPECT_EQ(cell("rendered"), "exact");
  EXPECT_NEAR(std::stod(cell("exact_fz_n")), 2.0, 1e-3);
  EXPECT_NEAR(std::stod(cell("box_fz_n")), 1.0, 1e-3);
  EXPECT_NEAR(std::stod(cell("box_depth")), 1.0, 1e-3);
}

TEST(ServoShadowTest, ComparisonLogWithAnImpossibleHeaderIsRefusedNamingTheFile) {
  const std::string path = shadow_temp("hb_shadow_hdr.hblog");
  test::HalfSpaceScene plane(0.f);
  {
    LogRecorder rec(path, 1000.0, VirtualDevice().spec(), RenderedAnswer::box);
    run_pressed(plane, &plane, 10, &rec);
    rec.finish();
  }
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 64u);
  const auto refused = [&](std::size_t at, std::uint32_t value, const std::string& expect) {
    std::string b = bytes;
    std::memcpy(&b[at], &value, 4);
    const std::string bad = shadow_temp("hb_shadow_bad.hblog");
    std::ofstream(bad, std::ios::binary) << b;
    try {
      read_servo_log(bad);
      ADD_FAILURE() << "accepted a header with " << value << " at byte " << at;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  };
  refused(44, 7, "rendered answer");     // neither box nor exact
  refused(12, 64, "record size");        // version 2 with version 1's record size
  refused(8, 1, "record size");          // version 1 with version 2's records
  refused(8, 3, "version 3");
}
