#include "analytic_scene.h"
#include "device/servo_log.h"
#include "device/servo_loop.h"
#include "device/virtual_device.h"
#include <gtest/gtest.h>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <thread>
#include <unistd.h>

using namespace hb;
using namespace std::chrono_literals;

namespace {

ServoOptions options() {
  ServoOptions o;
  o.request_realtime = false;
  // Default watchdog: a late tick in the recording is re-applied by the replay.
  o.safety.ramp_seconds = 0.05f;
  o.workspace.metres_per_unit = 1e-3;
  o.workspace.probe_length = 10.f;
  o.workspace.stiffness_n_per_m = 2000.0;
  return o;
}

std::string temp(const char* name) { return ::testing::TempDir() + name; }

void run_until_done(ServoLoop& loop, std::uint64_t ticks) {
  for (int i = 0; i < 5000 && loop.running() && loop.snapshot().tick < ticks; ++i)
    std::this_thread::sleep_for(1ms);
}

// Records about 300 ticks of the virtual device's circle over `scene` into `path`; returns
// the records the recorder dropped.
std::uint64_t record_circle(const std::string& path, const ContactQuery& scene, const ServoOptions& o) {
  VirtualDevice dev(circle_probe_trajectory(0.01f, 0.004f, 0.1), 1e-3);
  LogRecorder recorder(path, 1000.0, dev.spec());
  ServoLoop loop(dev, scene, o);
  loop.set_recorder(&recorder);
  loop.start();
  run_until_done(loop, 300);
  loop.stop();
  recorder.finish();
  return recorder.dropped();
}

// Replays the log at `log` over `scene`, recording into `out`; returns how the loop ended.
ServoExit replay_into(const std::string& log, const std::string& out, const ContactQuery& scene, const ServoOptions& o) {
  ReplayDevice dev(log);
  LogRecorder recorder(out, read_servo_log(log).rate_hz, dev.spec());
  ServoLoop loop(dev, scene, o);
  loop.set_recorder(&recorder);
  loop.start();
  for (int i = 0; i < 10000 && loop.running(); ++i) std::this_thread::sleep_for(1ms);
  loop.stop();
  recorder.finish();
  return loop.report().exit;
}

} // namespace

TEST(ReplayTest, ReplayingALogGivesTheSameForcesBitForBit) {
  const std::string rec1 = temp("hb_replay_1.hblog"), rec2 = temp("hb_replay_2.hblog");
  test::HalfSpaceScene scene(0.f);
  EXPECT_EQ(record_circle(rec1, scene, options()), 0u);
  const ServoLog original = read_servo_log(rec1);
  ASSERT_GE(original.records.size(), 300u);
  EXPECT_EQ(replay_into(rec1, rec2, scene, options()), ServoExit::end_of_stream);
  const ServoLog replay = read_servo_log(rec2);
  ASSERT_EQ(replay.records.size(), original.records.size());
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < original.records.size(); ++i) {
    const LogRecord &a = original.records[i], &b = replay.records[i];
    ASSERT_EQ(std::memcmp(a.force_n, b.force_n, sizeof a.force_n), 0) << "tick " << i;
    ASSERT_EQ(std::memcmp(a.position_m, b.position_m, sizeof a.position_m), 0) << "tick " << i;
    ASSERT_EQ(std::memcmp(&a.depth, &b.depth, sizeof a.depth), 0) << "tick " << i;
    ASSERT_EQ(a.contact, b.contact);
    ASSERT_EQ(a.time_s, b.time_s);
    contacts += a.contact;
  }
  EXPECT_GT(contacts, 0u);  // the trajectory does touch the surface
  std::remove(rec1.c_str());
  std::remove(rec2.c_str());
}

namespace {
// The half-space, counting the primes: with the previous tick's segment, with that segment
// moved once more by the last tick's motion (where the probe is heading), or another.
class PrimeCountingScene final : public ContactQuery {
public:
  Contact query(const Segment& s, const ForceLaw& law) const noexcept override {
    before_ = last_;
    last_ = s;
    ++queries_;
    return plane_.query(s, law);
  }
  void prime(const Segment& s, const ForceLaw& law) const noexcept override {
    const Segment ahead{last_.start + (last_.start - before_.start), last_.end + (last_.end - before_.end)};
    if (queries_ > 0 && s.start == last_.start && s.end == last_.end)
      ++primes_;
    else if (queries_ > 1 && s.start == ahead.start && s.end == ahead.end)
      ++ahead_;
    else
      ++not_last_;
    plane_.prime(s, law);
  }
  test::HalfSpaceScene plane_{0.f};
  mutable Segment last_{}, before_{};
  mutable std::size_t queries_ = 0, primes_ = 0, ahead_ = 0, not_last_ = 0;
};
} // namespace

TEST(ReplayTest, PrimingTheCachesWhereTheProbeIsAndIsHeadingChangesNoForce) {
  // Record with priming off, replay with it on (the default): the same forces bit for bit,
  // and every tick after the first primed with the tick before's segment, and after the
  // second with that segment moved by the last tick's motion.
  const std::string rec1 = temp("hb_prime_1.hblog"), rec2 = temp("hb_prime_2.hblog");
  test::HalfSpaceScene scene(0.f);
  ServoOptions unprimed = options();
  unprimed.prime = false;
  record_circle(rec1, scene, unprimed);
  const ServoLog original = read_servo_log(rec1);
  ASSERT_GE(original.records.size(), 300u);
  PrimeCountingScene counting;
  ServoOptions primed = options();
  ASSERT_TRUE(primed.prime);
  replay_into(rec1, rec2, counting, primed);
  const ServoLog replay = read_servo_log(rec2);
  ASSERT_EQ(replay.records.size(), original.records.size());
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < original.records.size(); ++i) {
    ASSERT_EQ(std::memcmp(original.records[i].force_n, replay.records[i].force_n, sizeof(float) * 3), 0) << "tick " << i;
    contacts += original.records[i].contact;
  }
  EXPECT_GT(contacts, 0u);
  // Every tick but the first was primed (and the end of the stream, found after a prime),
  // with the tick before's segment and, the probe moving on a circle, with it moved ahead.
  EXPECT_GE(counting.primes_ + 1, counting.queries_);
  EXPECT_LE(counting.primes_, counting.queries_);
  EXPECT_GE(counting.queries_, original.records.size());
  EXPECT_EQ(counting.not_last_, 0u);
  EXPECT_GE(counting.ahead_ + 2, counting.primes_);
  EXPECT_LE(counting.ahead_, counting.primes_);
  std::remove(rec1.c_str());
  std::remove(rec2.c_str());
}

TEST(ReplayTest, LogRoundTripsRecords) {
  const std::string path = temp("hb_log_roundtrip.hblog");
  DeviceSpec spec = virtual_device_spec();
  {
    LogRecorder rec(path, 500.0, spec, 1024);
    for (int i = 0; i < 3000; ++i) {
      LogRecord r;
      r.tick = i;
      r.time_s = i * 0.002;
      r.force_n[1] = static_cast<float>(i);
      while (!rec.push(r)) std::this_thread::sleep_for(1ms);  // tiny ring: wait for the writer
    }
    rec.finish();
    EXPECT_EQ(rec.written(), 3000u);
  }
  const ServoLog log = read_servo_log(path);
  EXPECT_EQ(log.rate_hz, 500.0);
  EXPECT_EQ(log.spec.max_force_n, spec.max_force_n);
  ASSERT_EQ(log.records.size(), 3000u);
  for (int i = 0; i < 3000; ++i) {
    EXPECT_EQ(log.records[i].tick, static_cast<std::uint64_t>(i));
    EXPECT_EQ(log.records[i].force_n[1], static_cast<float>(i));
  }
  std::remove(path.c_str());
}

TEST(ReplayTest, TruncatedOrForeignLogsAreRejectedNamingTheFile) {
  const std::string path = temp("hb_log_truncated.hblog");
  {
    LogRecorder rec(path, 1000.0, virtual_device_spec());
    rec.push(LogRecord{});
    rec.finish();
  }
  std::ofstream(path, std::ios::binary | std::ios::app).write("xyz", 3);
  try {
    read_servo_log(path);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos);
  }
  std::ofstream(path, std::ios::binary).write("not a log at all, definitely not 64 bytes of header..........", 62);
  EXPECT_THROW(read_servo_log(path), InvalidInput);
  std::remove(path.c_str());
  EXPECT_THROW(read_servo_log(path), IoError);
}

TEST(ReplayTest, ReplayDeviceEndsWithEndOfStream) {
  ServoLog log;
  log.records.resize(3);
  log.records[1].position_m[0] = 0.5f;
  ReplayDevice dev(log);
  dev.open();
  DeviceState s;
  EXPECT_EQ(dev.read_state(s), DeviceStatus::ok);
  EXPECT_EQ(dev.read_state(s), DeviceStatus::ok);
  EXPECT_EQ(s.position_m.x(), 0.5f);
  EXPECT_EQ(dev.read_state(s), DeviceStatus::ok);
  EXPECT_EQ(dev.read_state(s), DeviceStatus::end_of_stream);
}

// Found by fuzzing: a replay trusted the log header. Rates no loop can run (0.05 Hz never
// returned; 1e-300 Hz overflowed), a negative stiffness (every force reversed into the
// surface) and an infinite, NaN, zero or negative force maximum are refused at reading.
namespace {

void expect_log_refused(double rate, const DeviceSpec& spec, const std::string& cause) {
  const std::string path = temp(("hb_log_header_" + std::to_string(::getpid()) + ".hblog").c_str());
  {
    LogRecorder rec(path, rate, spec);
    rec.push(LogRecord{});
    rec.finish();
  }
  try {
    read_servo_log(path);
    ADD_FAILURE() << "no error for rate " << rate << ", " << cause;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(cause), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

} // namespace

TEST(ReplayTest, LogRateNoServoLoopCanRunIsRefused) {
  for (double rate : {0.05, 1e-300, 0.0, -1000.0, 1e9, std::nan(""), HUGE_VAL})
    expect_log_refused(rate, virtual_device_spec(), "servo log rate");
}

TEST(ReplayTest, LogDeviceSpecNoDeviceCanHaveIsRefused) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (float stiffness : {-3000.f, 0.f, nan, inf, 1e30f}) {
    DeviceSpec s = virtual_device_spec();
    s.max_stiffness_n_per_m = stiffness;
    expect_log_refused(1000.0, s, "maximum stiffness");
  }
  for (float force : {inf, 1e30f, nan, 0.f, -8.f}) {
    DeviceSpec s = virtual_device_spec();
    s.max_force_n = force;
    expect_log_refused(1000.0, s, "maximum force");
  }
  DeviceSpec s = virtual_device_spec();
  s.workspace_radius_m = -0.04f;
  expect_log_refused(1000.0, s, "workspace radius");
  s = virtual_device_spec();
  s.max_continuous_force_n = 2.f * s.max_force_n;
  expect_log_refused(1000.0, s, "continuous force");
  EXPECT_EQ(device_spec_problem(virtual_device_spec()), "");
}

TEST(ReplayTest, LoopRefusesAReplayWhoseSpecWouldReverseTheForces) {
  // A log built in memory (the reader would refuse its spec): the loop refuses it too.
  ServoLog log;
  log.spec = virtual_device_spec();
  log.spec.max_stiffness_n_per_m = -3000.f;
  log.records.resize(50);
  ReplayDevice dev(log);
  test::HalfSpaceScene scene(0.f);
  ServoLoop loop(dev, scene, options());
  EXPECT_THROW(loop.start(), InvalidInput);
}
