// The god-object proxy in the servo loop (ServoOptions::contact_law, `servo --law proxy`): the
// virtual device moves the probe in a crisp concave groove (the stability suite's generated
// 90-degree V-groove, flat shaded) baked to a refined box scene that drives the device, with
// exact Embree on the same mesh in shadow, each answer with its own proxy. What is asserted is
// read back from the loop's comparison log: both answers' forces before safety, every tick.
#include "servo_test_support.h"
#include "analytic_scene.h"
#include "device/servo_log.h"
#include "device/servo_loop.h"
#include "device/virtual_device.h"
#include "errors.h"
#include "stability/stability_suite.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "scene/box_scene.h"
#include <gtest/gtest.h>
#include <chrono>
#include <cstdio>
#include <string>
#include <unistd.h>
#include <cmath>
#include <memory>
#include <thread>
#include <vector>

using namespace hb;

namespace {

// The 90-degree crisp groove: crease along y through the origin, walls z = |x| (mm), open
// towards +z; baked as the stability suite bakes its generated objects (m 16, n 8, refined).
struct ProxyGroove {
  TriangleMesh mesh;
  std::unique_ptr<BoxScene> box;
  std::unique_ptr<ExactQuery> exact;
};

const ProxyGroove& proxy_groove() {
  static const ProxyGroove g = [] {
    ProxyGroove s;
    s.mesh = make_v_groove(90.f, false);
    BakeOptions bo;
    bo.params.m = 16;
    bo.params.n = 8;
    bo.refine = true;
    s.box = std::make_unique<BoxScene>(bake_scene(s.mesh, {}, bo, SourceInfo{}));
    s.exact = std::make_unique<ExactQuery>(s.mesh);
    return s;
  }();
  return g;
}

// The walls' outward normals (x < 0: z = -x; x > 0: z = x).
const Vec3 kLeftWall = Vec3(1.f, 0.f, 1.f).normalized();
const Vec3 kRightWall = Vec3(-1.f, 0.f, 1.f).normalized();

// One tick as the comparison log has it: [0] the box (drives), [1] exact (shadow).
struct ProxyTick {
  Vec3 tip_mm;
  bool contact[2] = {false, false};
  Vec3 force[2];
  Vec3 normal[2];
  Vec3 sent;  // after the energy guard and safety
};

ServoOptions proxy_options(ContactLaw law) {
  ServoOptions o = test::servo_test_options();  // mm, 10 mm probe, k = 1000 N/m
  o.contact_law = law;
  o.workspace.model_origin = Vec3::Zero();
  o.workspace.probe_direction = Vec3(0.f, 0.f, -1.f);
  return o;
}

// Runs `device` for about `ticks` ticks over the groove's box with exact in shadow.
std::vector<ProxyTick> run_groove(HapticDevice& device, const ServoOptions& o, std::uint64_t ticks,
                                  ServoReport* report = nullptr) {
  const ProxyGroove& g = proxy_groove();
  const SceneProbe box(*g.box);
  // One file per test and process: ctest runs the tests in parallel processes.
  const std::string path = ::testing::TempDir() + "hb_proxy_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                           std::to_string(::getpid()) + ".hblog";
  ServoLog log;
  {
    LogRecorder rec(path, o.rate_hz, device.spec(), RenderedAnswer::box);
    ServoLoop loop(device, box, o);
    loop.set_shadow(g.exact.get());
    loop.set_recorder(&rec);
    loop.start();
    test::wait_ticks(loop, ticks, 20000);
    loop.stop();
    rec.finish();
    if (report) *report = loop.report();
  }
  log = read_servo_log(path);
  std::remove(path.c_str());
  std::vector<ProxyTick> out;
  if (!log.comparison || log.shadow.size() != log.records.size()) return out;
  for (std::size_t i = 0; i < log.records.size(); ++i) {
    const LogRecord& r = log.records[i];
    const ShadowRecord& s = log.shadow[i];
    ProxyTick t;
    t.tip_mm = o.workspace.model_origin + Vec3(r.position_m[0], r.position_m[1], r.position_m[2]) * 1000.f;
    t.contact[0] = r.contact != 0;
    t.contact[1] = s.shadow_contact != 0;
    t.force[0] = Vec3(s.drive_force_n[0], s.drive_force_n[1], s.drive_force_n[2]);
    t.force[1] = Vec3(s.shadow_force_n[0], s.shadow_force_n[1], s.shadow_force_n[2]);
    t.normal[0] = Vec3(s.drive_normal[0], s.drive_normal[1], s.drive_normal[2]);
    t.normal[1] = Vec3(s.shadow_normal[0], s.shadow_normal[1], s.shadow_normal[2]);
    t.sent = Vec3(r.force_n[0], r.force_n[1], r.force_n[2]);
    out.push_back(t);
  }
  return out;
}

// The tip pressed 0.8 mm into the crease, wobbling +-0.05 mm across the bisector at 4 Hz (it
// reaches the depth in 0.2 s).
Vec3 wobble_in_crease(double t) {
  const double z = std::max(-0.0008, 0.001 - 0.009 * t);
  return Vec3(float(5e-5 * std::sin(2.0 * 3.14159265358979 * 4.0 * t)), 0.0013f, float(z));
}

// T4's figures over ticks [from, end): lateral ripple (rms F_x / mean |F|), wall switches a
// second (the answer's normal leaning to the other wall), and the largest change of the force
// from one tick to the next, N.
struct GrooveChatter {
  double ripple = 99, switches_per_s = 99, max_jump_n = 99;
  std::size_t contact_ticks = 0;
};

GrooveChatter groove_chatter(const std::vector<ProxyTick>& ticks, int which, std::size_t from, double rate_hz) {
  GrooveChatter c;
  double lat2 = 0, fsum = 0, jump = 0;
  int switches = 0, last = 0;
  for (std::size_t i = from; i < ticks.size(); ++i) {
    const ProxyTick& t = ticks[i];
    if (!t.contact[which]) continue;
    ++c.contact_ticks;
    lat2 += double(t.force[which].x()) * t.force[which].x();
    fsum += t.force[which].norm();
    const int wall = t.normal[which].x() > 0.05f ? 1 : (t.normal[which].x() < -0.05f ? -1 : 0);
    if (wall != 0 && last != 0 && wall != last) ++switches;
    if (wall != 0) last = wall;
    if (i > from && ticks[i - 1].contact[which])
      jump = std::max(jump, double((t.force[which] - ticks[i - 1].force[which]).norm()));
  }
  if (c.contact_ticks == 0 || !(fsum > 0)) return c;
  c.ripple = std::sqrt(lat2 / c.contact_ticks) / (fsum / c.contact_ticks);
  c.switches_per_s = switches / ((ticks.size() - from) / rate_hz);
  c.max_jump_n = jump;
  return c;
}

// The force as a combination a n_left + b n_right (+ y): a god-object's force is a
// non-negative combination of the planes that hold it, so a or b below zero pushes into a wall.
void wall_coefficients(const Vec3& f, double& a, double& b) {
  a = f.dot(kLeftWall);  // the two normals are orthogonal at 90 degrees
  b = f.dot(kRightWall);
}

// Distance (mm) from the tip to the free side {z >= |x|}: to the nearer wall's plane, or to
// the crease line below it.
float distance_to_free_side(const Vec3& tip_mm) {
  const float x = std::fabs(tip_mm.x()), z = tip_mm.z();
  if (z >= x) return 0.f;
  if (z <= -x) return std::sqrt(x * x + z * z);
  return (x - z) / std::sqrt(2.f);
}

// A device that stalls: the virtual device, whose read number `at` sleeps `stall_ms` first
// (the servo thread is held up; the trajectory itself carries the motion the stall misses).
class StallingDevice final : public HapticDevice {
public:
  StallingDevice(Trajectory trajectory, std::uint64_t at, int stall_ms)
      : inner_(std::move(trajectory), 1e-3), at_(at), stall_ms_(stall_ms) {}
  const DeviceSpec& spec() const noexcept override { return inner_.spec(); }
  void open() override { inner_.open(); }
  void close() noexcept override { inner_.close(); }
  DeviceStatus read_state(DeviceState& out) noexcept override {
    if (inner_.reads() == at_) std::this_thread::sleep_for(std::chrono::milliseconds(stall_ms_));
    return inner_.read_state(out);
  }
  DeviceStatus write_force(const Vec3& f) noexcept override { return inner_.write_force(f); }

private:
  VirtualDevice inner_;
  std::uint64_t at_;
  int stall_ms_;
};

} // namespace

TEST(ServoProxyTest, PenaltyIsTheDefaultAndTheReportNamesTheLaw) {
  EXPECT_EQ(ServoOptions{}.contact_law, ContactLaw::penalty);
  EXPECT_EQ(contact_law("proxy"), ContactLaw::proxy);
  EXPECT_STREQ(to_string(ContactLaw::proxy), "proxy");
  EXPECT_THROW(contact_law("spring"), InvalidInput);
  test::HalfSpaceScene plane(0.f);
  for (ContactLaw law : {ContactLaw::penalty, ContactLaw::proxy}) {
    VirtualDevice dev;
    dev.set_target(Vec3(0.f, 0.f, -0.002f));
    ServoLoop loop(dev, plane, proxy_options(law));
    loop.start();
    test::wait_ticks(loop, 100);
    loop.stop();
    EXPECT_EQ(loop.report().contact_law, law);
    // The proxy's counters only with the proxy: one contact episode, no fallback.
    EXPECT_EQ(loop.report().proxy.seeds, law == ContactLaw::proxy ? 1u : 0u);
    EXPECT_EQ(loop.report().proxy.fallbacks, 0u);
    EXPECT_EQ(loop.report().proxy.contact_ticks, law == ContactLaw::proxy ? loop.report().ticks : 0u);
  }
}

TEST(ServoProxyTest, ProxyOptionsThatCannotWorkAreRefusedAtStart) {
  test::HalfSpaceScene plane(0.f);
  VirtualDevice dev;
  ServoOptions o = proxy_options(ContactLaw::proxy);
  o.proxy.clearance_m = 0.f;
  ServoLoop loop(dev, plane, o);
  EXPECT_THROW(loop.start(), InvalidInput);
  ServoOptions q = proxy_options(ContactLaw::proxy);
  q.proxy.max_queries = 0;
  ServoLoop loop2(dev, plane, q);
  EXPECT_THROW(loop2.start(), InvalidInput);
}

TEST(ServoProxyTest, FlatWallFeelsTheSameUnderBothLawsButForTheClearance) {
  test::HalfSpaceScene plane(0.f), same(0.f);
  Vec3 desired[2];
  for (int i = 0; i < 2; ++i) {
    VirtualDevice dev;
    dev.set_target(Vec3(0.f, 0.f, -0.002f));
    ServoLoop loop(dev, plane, proxy_options(i ? ContactLaw::proxy : ContactLaw::penalty));
    loop.set_shadow(&same);
    loop.start();
    test::wait_ticks(loop, 100);
    const ServoSnapshot s = loop.snapshot();
    loop.stop();
    desired[i] = Vec3(s.desired_force_n[0], s.desired_force_n[1], s.desired_force_n[2]);
    // Both answers by the same law, each its own proxy: they agree on every tick.
    EXPECT_EQ(loop.report().shadow.drive_only + loop.report().shadow.shadow_only, 0u);
    EXPECT_LE(loop.report().shadow.force_diff_max_n, 1e-4);
  }
  EXPECT_NEAR(desired[0].z(), 2.f, 1e-3f);  // 1000 N/m x 2 mm
  EXPECT_NEAR(desired[1].z(), 2.f, 2e-3f);  // the proxy rests 0.5 um in front of the wall
  EXPECT_NEAR((desired[1] - desired[0]).norm(), 0.f, 2e-3f);
}

TEST(ServoProxyTest, CrispGrooveChattersUnderThePenaltyLawAndIsCalmWithTheProxy) {
  GrooveChatter figures[2][2];  // [law][box, exact]
  for (int law = 0; law < 2; ++law) {
    VirtualDevice dev(wobble_in_crease, 1e-3);
    const ServoOptions o = proxy_options(law ? ContactLaw::proxy : ContactLaw::penalty);
    const auto ticks = run_groove(dev, o, 1500);
    ASSERT_GE(ticks.size(), 1000u);
    for (int which = 0; which < 2; ++which) {
      figures[law][which] = groove_chatter(ticks, which, 500, o.rate_hz);  // after 0.5 s
      EXPECT_GE(figures[law][which].contact_ticks, ticks.size() - 500 - 5) << "law " << law << " answer " << which;
    }
  }
  for (int which = 0; which < 2; ++which) {
    const GrooveChatter& pen = figures[0][which];
    const GrooveChatter& prx = figures[1][which];
    const char* name = which ? "exact" : "box";
    // Penalty: the force follows whichever wall the stylus meets, flipping at each crossing of
    // the bisector (8 a second) by about 0.85 N.
    EXPECT_GT(pen.ripple, 0.3) << name;
    EXPECT_GE(pen.switches_per_s, 4.0) << name;
    EXPECT_GT(pen.max_jump_n, 0.4) << name;
    // Proxy: held on the crease line by both walls, k (proxy - tip) turns with the tip.
    EXPECT_LE(prx.ripple, 0.07) << name;
    EXPECT_LE(prx.switches_per_s, 1.0) << name;
    EXPECT_LT(prx.max_jump_n, 0.05) << name;
    EXPECT_LT(prx.max_jump_n, 0.1 * pen.max_jump_n) << name;
  }
}

TEST(ServoProxyTest, ProxyInTheLoopNeverPushesIntoTheObject) {
  // The tip sweeps +-3 mm across the groove and up to 3 mm in and out of it, along the crease
  // too: contact episodes begin and end, the proxy slides from one wall onto both.
  const Trajectory sweep = [](double t) {
    const double w = 2.0 * 3.14159265358979;
    return Vec3(float(0.003 * std::sin(w * 1.1 * t)), float(0.0013 + 0.002 * std::sin(w * 0.7 * t)),
                float(-0.001 + 0.002 * std::sin(w * 1.7 * t)));
  };
  VirtualDevice dev(sweep, 1e-3);
  ServoReport report;
  const auto ticks = run_groove(dev, proxy_options(ContactLaw::proxy), 2500, &report);
  ASSERT_GE(ticks.size(), 2000u);
  std::size_t contact[2] = {0, 0}, into[2] = {0, 0}, inside_no_contact[2] = {0, 0};
  for (const ProxyTick& t : ticks) {
    // Inside the material (below both walls' planes, deeper than a micron) with the vertical
    // stylus: every answer must have the contact.
    const bool inside = t.tip_mm.z() < std::fabs(t.tip_mm.x()) - 1e-3f;
    for (int which = 0; which < 2; ++which) {
      if (!t.contact[which]) {
        inside_no_contact[which] += inside;
        continue;
      }
      ++contact[which];
      double a, b;
      wall_coefficients(t.force[which], a, b);
      if (a < -1e-3 || b < -1e-3 || std::fabs(t.force[which].y()) > 1e-3f) ++into[which];
      // k times the distance to the proxy, the nearest free point: never stronger than the
      // tip's distance to the free side allows.
      const float k_distance = 1000.f * distance_to_free_side(t.tip_mm) * 1e-3f;
      EXPECT_LE(t.force[which].norm(), 1.01f * k_distance + 2e-3f) << "tip " << t.tip_mm.transpose();
    }
  }
  for (int which = 0; which < 2; ++which) {
    EXPECT_GT(contact[which], 500u) << which;
    EXPECT_EQ(into[which], 0u) << (which ? "exact" : "box");
    EXPECT_EQ(inside_no_contact[which], 0u) << (which ? "exact" : "box");
  }
  EXPECT_GE(report.proxy.seeds, 3u);  // several episodes
  EXPECT_GE(report.shadow_proxy.seeds, 3u);
  EXPECT_EQ(report.proxy.max_planes, 2u);  // one wall, then both in the crease
}

TEST(ServoProxyTest, StallWhileInContactWithTheProxyDoesNotPopThrough) {
  // Pressing down the crease at 20 mm/s to 3 mm; at 150 ms (2 mm in) the servo thread stalls
  // for 20 ms in the device read while the hand goes on 0.4 mm: the next tick's tip is 0.4 mm
  // deeper than the proxy's last one.
  constexpr std::uint64_t kStallRead = 150;
  const Trajectory press = [](double t) {
    if (t >= kStallRead * 1e-3) t += 0.02;  // the motion the stall misses
    return Vec3(5e-5f, 0.0013f, float(std::max(-0.003, 0.001 - 0.02 * t)));
  };
  StallingDevice dev(press, kStallRead, 20);
  const ServoOptions o = proxy_options(ContactLaw::proxy);
  ServoReport report;
  const auto ticks = run_groove(dev, o, 600, &report);
  ASSERT_GE(ticks.size(), 500u);
  // The stall happened: an overrun that skipped the deadlines it missed, and the jump.
  EXPECT_GE(report.overruns, 1u);
  EXPECT_GE(report.skipped, 15u);
  ASSERT_GT(ticks.size(), kStallRead);
  EXPECT_NEAR(ticks[kStallRead - 1].tip_mm.z() - ticks[kStallRead].tip_mm.z(), 0.42f, 0.01f);
  std::size_t first = ticks.size();
  for (std::size_t i = 0; i < ticks.size() && first == ticks.size(); ++i)
    if (ticks[i].tip_mm.z() < -0.01f) first = i;
  ASSERT_LT(first, kStallRead);
  for (std::size_t i = first; i < ticks.size(); ++i) {
    const ProxyTick& t = ticks[i];
    const float k_distance = 1000.f * distance_to_free_side(t.tip_mm) * 1e-3f;
    for (int which = 0; which < 2; ++which) {
      ASSERT_TRUE(t.contact[which]) << "tick " << i << " answer " << which;
      double a, b;
      wall_coefficients(t.force[which], a, b);
      EXPECT_GE(a, -1e-3) << "tick " << i;
      EXPECT_GE(b, -1e-3) << "tick " << i;
      // k times the tip's distance to the free side (the crease line once 0.05 mm deep), up
      // to the 0.5 um clearance: the proxy stays where it belongs across the stall.
      EXPECT_NEAR(t.force[which].norm(), k_distance, 2e-3f) << "tick " << i << " answer " << which;
    }
    // What the device gets keeps pushing out of the groove through the stall and after it.
    if (i > first + 10) {
      EXPECT_GT(t.sent.z(), 0.05f) << "tick " << i;
    }
  }
  // After the ramp the full force is back.
  EXPECT_NEAR(ticks.back().sent.z(), 3.f, 0.05f);
  EXPECT_EQ(report.proxy.fallbacks, 0u);
  EXPECT_EQ(report.proxy.seeds, 1u);  // one episode: the proxy was never lost
  EXPECT_EQ(report.shadow_proxy.seeds, 1u);
}
