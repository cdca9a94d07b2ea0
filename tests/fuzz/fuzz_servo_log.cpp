// libFuzzer target: the servo log reader plus a replay through the real servo loop.
//
//  1. The input is a log file. A rejected log must give an hb::Error naming the file.
//  2. An accepted log (its first 12 records) is replayed by ServoLoop over the analytic plane
//     z = 0 (solid below), through a device that wraps the ReplayDevice and keeps every force
//     the loop commands. The rate is raised to 20 kHz so that one input costs under a
//     millisecond (the log's own rate, checked by the reader, only sets the ramp lengths).
//  3. Every commanded force must be finite, within the log's device maximum, and point out of
//     the plane (+z, no x or y component): never into the surface.
//  4. A comparison log (version 2, `servo --exact`) has a shadow record per record and a known
//     rendered answer; its replay runs a shadow query too, which must change nothing sent.
#include "device/plane_scene.h"
#include "device/servo_log.h"
#include "device/servo_loop.h"
#include "fuzz_support.h"

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace {

/// The replay, and a record of what the loop commanded.
class CheckedReplay final : public hb::HapticDevice {
public:
  explicit CheckedReplay(hb::ServoLog log) : replay_(std::move(log)) { forces_.reserve(64); }
  const hb::DeviceSpec& spec() const noexcept override { return replay_.spec(); }
  void open() override { replay_.open(); }
  void close() noexcept override { replay_.close(); }
  hb::DeviceStatus read_state(hb::DeviceState& out) noexcept override { return replay_.read_state(out); }
  hb::DeviceStatus write_force(const hb::Vec3& f) noexcept override {
    if (forces_.size() < forces_.capacity()) forces_.push_back(f);
    return hb::DeviceStatus::ok;
  }
  const std::vector<hb::Vec3>& forces() const { return forces_; }

private:
  hb::ReplayDevice replay_;
  std::vector<hb::Vec3> forces_;
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hb::fuzz::write_scratch(".hblog", data, size);
  hb::ServoLog log;
  try {
    log = hb::read_servo_log(path);
  } catch (const hb::Error& e) {
    hb::fuzz::check_rejection(e, path);
    return 0;
  }
  if (hb::device_spec_problem(log.spec) != "") hb::fuzz::fail("accepted a log whose device spec is impossible");
  if (!(log.rate_hz >= hb::kMinServoRateHz && log.rate_hz <= hb::kMaxServoRateHz))
    hb::fuzz::fail("accepted a log rate outside the servo range");
  if (log.comparison ? log.shadow.size() != log.records.size() : !log.shadow.empty())
    hb::fuzz::fail("a comparison log without one shadow record per record, or a plain log with some");
  if (log.rendered != hb::RenderedAnswer::box && log.rendered != hb::RenderedAnswer::exact)
    hb::fuzz::fail("accepted an unknown rendered answer");
  const bool comparison = log.comparison;
  if (log.records.empty()) return 0;
  if (log.records.size() > 12) log.records.resize(12);
  if (log.shadow.size() > 12) log.shadow.resize(12);
  const float max_force = log.spec.max_force_n;
  CheckedReplay device(std::move(log));
  const hb::PlaneScene plane(0.f);
  hb::ServoOptions o;
  o.rate_hz = 20000.0;
  o.request_realtime = false;
  o.spin_s = 0.0;
  o.safety.ramp_seconds = 0.f;  // full forces from the first tick: the clamp is what is tested
  hb::Bounds cube;  // an 80 mm cube around the plane, as `servo plane`
  cube.min = hb::Vec3::Constant(-40.f);
  cube.max = hb::Vec3::Constant(40.f);
  o.workspace = hb::make_workspace(cube);
  o.workspace.stiffness_n_per_m = 1e7;  // far above any device: the stiffness limit must hold it
  hb::ServoLoop loop(device, plane, o);
  // A comparison log replays with a shadow answer too (a plane 1 unit higher): it must change
  // nothing the device is sent.
  const hb::PlaneScene shadow(1.f);
  if (comparison) loop.set_shadow(&shadow);
  try {
    loop.start();
  } catch (const hb::Error& e) {
    hb::fuzz::fail(std::string("an accepted log does not start the loop: ") + e.what());
  }
  for (int i = 0; i < 2000 && loop.running(); ++i) std::this_thread::sleep_for(std::chrono::microseconds(100));
  loop.stop();
  for (const hb::Vec3& f : device.forces()) {
    if (!f.allFinite()) hb::fuzz::fail("a non-finite force was commanded");
    if (f.norm() > max_force * (1.f + 1e-5f)) hb::fuzz::fail("a force above the device maximum was commanded");
    if (f.x() != 0.f || f.y() != 0.f || f.z() < 0.f) hb::fuzz::fail("a force into the surface was commanded");
  }
  return 0;
}
