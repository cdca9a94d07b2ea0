// Servo loop.
// 1. start(): validate options, limit the stiffness to the device's, open the device, spawn.
// 2. Thread: request SCHED_FIFO (report granted or strerror), then tick on absolute deadlines:
//    clock_nanosleep(TIMER_ABSTIME) to `deadline - spin`, busy-wait to the deadline.
// 2b. With ServoOptions::prime, the busy-wait begins with the scene's prime() of the last
//    tick's segment: after a millisecond's sleep the caches hold other processes' lines, and
//    the tick's query (a few micrometres from the last) then finds its own. When the probe
//    moved, the segment one more tick's motion ahead is primed too (the cells it enters). Measured on the
//    armadillo (servo --device virtual): see the README's servo figures.
// 3. Tick: read device -> map to a probe segment -> scene.query -> safety -> write force;
//    record period, |period error|, query and compute (query + safety) in preallocated
//    histograms; publish the snapshot; push a log record.
// 4. A tick ending after the next deadline is an overrun; deadlines already past are skipped
//    (no burst of catch-up ticks), and the safety watchdog sees the lateness.
// 5. Disconnect or end of stream ends the loop: zero force (when possible), report, exit.
// 6. With a shadow query (set_shadow), after the force is written the same segment is asked
//    of it too; the two answers are compared (counts, |dF| and angle histograms) and logged.
// 7. ContactLaw::proxy: start() makes a GodObject over the scene (and one over the shadow);
//    each tick steps it with the tick's segment instead of asking the scene once, so the
//    driving and the shadow answer are the same law, each with its own proxy state.
#include "device/servo_loop.h"
#include "device/servo_log.h"
#include <pthread.h>
#include <sys/prctl.h>
#include <sched.h>
#include <time.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace hb {
namespace {

std::int64_t now_ns() noexcept {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

void sleep_until_ns(std::int64_t t) noexcept {
  timespec ts;
  ts.tv_sec = static_cast<time_t>(t / 1000000000LL);
  ts.tv_nsec = static_cast<long>(t % 1000000000LL);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

inline void cpu_relax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

void to_array(const Vec3& v, float* out) noexcept {
  out[0] = v.x();
  out[1] = v.y();
  out[2] = v.z();
}

} // namespace

const char* to_string(ServoExit e) noexcept {
  switch (e) {
    case ServoExit::not_started: return "not started";
    case ServoExit::stopped: return "stopped";
    case ServoExit::end_of_stream: return "end of stream";
    case ServoExit::disconnected: return "disconnected";
  }
  return "unknown";
}

TimingStats timing_stats(const TimingHistogram& h) {
  TimingStats s;
  s.count = h.count();
  s.p50_us = h.percentile_ns(0.5) * 1e-3;
  s.p99_us = h.percentile_ns(0.99) * 1e-3;
  s.p999_us = h.percentile_ns(0.999) * 1e-3;
  s.max_us = h.max_ns() * 1e-3;
  s.mean_us = h.mean_ns() * 1e-3;
  return s;
}

ServoLoop::ServoLoop(HapticDevice& device, const ContactQuery& scene, ServoOptions options)
    : device_(device),
      scene_(scene),
      options_(options),
      safety_(device.spec(), options.safety, options.rate_hz > 0 ? 1.0 / options.rate_hz : 1e-3),
      guard_(options.energy_guard, options.rate_hz > 0 ? 1.0 / options.rate_hz : 1e-3),
      period_hist_(1000, 20000),        // 1 us bins up to 20 ms
      period_error_hist_(1000, 20000),
      compute_hist_(10, 100000),        // 10 ns bins up to 1 ms
      query_hist_(10, 100000),
      window_hist_(10000, 2000),        // 10 us bins up to 20 ms: the live rate window
      shadow_query_hist_(10, 100000),
      force_diff_hist_(1, 200000),      // 0.1 mN bins up to 20 N
      angle_hist_(1, 18001) {}          // 0.01 degree bins up to 180 degrees

ServoLoop::~ServoLoop() {
  try {
    stop();
  } catch (...) {
  }
}

void ServoLoop::start() {
  if (thread_.joinable()) throw std::logic_error("servo loop: already started");
  if (!(options_.rate_hz >= kMinServoRateHz && options_.rate_hz <= kMaxServoRateHz))
    throw InvalidInput("servo loop: rate " + std::to_string(options_.rate_hz) + " Hz is outside [1, 20000]");
  if (const std::string why = device_spec_problem(device_.spec()); !why.empty())
    throw InvalidInput("servo loop: " + device_.spec().name + ": " + why);
  const Workspace& ws = options_.workspace;
  if (!(std::isfinite(ws.stiffness_n_per_m) && ws.stiffness_n_per_m > 0 && std::isfinite(float(ws.stiffness_n_per_m)) &&
        std::isfinite(ws.metres_per_unit) && float(ws.metres_per_unit) > 0.f && std::isfinite(1.0 / ws.metres_per_unit)))
    throw InvalidInput("servo loop: the workspace needs a finite positive stiffness and metres per unit");
  if (!(ws.probe_length > 0) || !std::isfinite(ws.probe_length) || !ws.model_origin.allFinite() ||
      !ws.probe_direction.allFinite() || ws.probe_direction.norm() < 1e-6f)
    throw InvalidInput("servo loop: the workspace needs a finite model origin, a positive probe length and a "
                       "non-zero probe direction");
  if (options_.contact_law == ContactLaw::proxy &&
      !(std::isfinite(options_.proxy.clearance_m) && options_.proxy.clearance_m > 0.f && options_.proxy.max_queries >= 1))
    throw InvalidInput("servo loop: the proxy needs a finite positive clearance and at least one query a tick");
  options_.workspace.probe_direction.normalize();

  report_ = ServoReport{};
  report_.nominal_rate_hz = options_.rate_hz;
  const DeviceSpec& spec = device_.spec();
  // What the law can make the device feel: k at any tilt with the normal depth law, up to
  // k / cos(75 deg) with the depth along the segment (the workspace's metres per unit and its
  // inverse, the device to the model, cancel).
  const double felt = options_.workspace.stiffness_n_per_m * felt_stiffness_factor(options_.workspace.law());
  if (options_.limit_stiffness && felt > spec.max_stiffness_n_per_m && felt > 0) {
    options_.workspace.stiffness_n_per_m *= spec.max_stiffness_n_per_m / felt;
    report_.stiffness_limited = true;
  }
  report_.stiffness_n_per_m = float(options_.workspace.stiffness_n_per_m);
  report_.contact_law = options_.contact_law;
  proxy_.reset();
  shadow_proxy_.reset();
  if (options_.contact_law == ContactLaw::proxy) {
    proxy_.emplace(scene_, options_.proxy);
    if (shadow_) shadow_proxy_.emplace(*shadow_, options_.proxy);
  }
  coupling_.reset();
  shadow_coupling_.reset();
  if (options_.tool) {
    coupling_.emplace(scene_, *options_.tool, options_.workspace, options_.coupling);
    if (shadow_) shadow_coupling_.emplace(*shadow_, *options_.tool, options_.workspace, options_.coupling);
  }
  safety_ = SafetyFilter(spec, options_.safety, 1.0 / options_.rate_hz);
  guard_ = EnergyGuard(options_.energy_guard, 1.0 / options_.rate_hz);
  for (auto* h : {&period_hist_, &period_error_hist_, &compute_hist_, &query_hist_, &shadow_query_hist_,
                  &force_diff_hist_, &angle_hist_})
    h->clear();

  device_.open();
  opened_ = true;
  stop_.store(false);
  running_.store(true, std::memory_order_release);
  try {
    thread_ = std::thread([this] { run(); });
  } catch (...) {
    running_.store(false);
    device_.close();
    opened_ = false;
    throw;
  }
}

void ServoLoop::stop() {
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  if (opened_) {
    device_.close();
    opened_ = false;
  }
}

void ServoLoop::request_realtime() noexcept {
  ServoReport& rep = report_;
  // Wake-ups on time without SCHED_FIFO too: a normal thread's sleeps may end up to its timer
  // slack (50 us by default) late, which is the whole busy-wait window (and its priming).
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  rep.realtime_requested = options_.request_realtime;
  if (options_.request_realtime) {
    sched_param sp{};
    sp.sched_priority = std::clamp(options_.realtime_priority, 1, 99);
    const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    rep.realtime_granted = rc == 0;
    rep.realtime_message = rc == 0 ? "SCHED_FIFO priority " + std::to_string(sp.sched_priority)
                                   : std::string("SCHED_FIFO refused: ") + std::strerror(rc);
  } else {
    rep.realtime_message = "not requested";
  }
}

Contact ServoLoop::couple(ToolCoupling& coupling, const Segment& seg, const ForceLaw& law) noexcept {
  ToolPose device;
  device.position = seg.end;
  const ToolCouplingStep& s = coupling.step(device, law);
  Contact c;
  c.contact = s.touching;
  c.force = s.force;
  const float f = s.force.norm();
  c.normal = f > 0.f ? Vec3(s.force / f) : Vec3(Vec3::Zero());
  c.point = s.tool.position;
  c.depth = (s.tool.position - seg.end).norm();
  if (&coupling == &*coupling_) {
    report_.tool_max_torque_nm = std::max(report_.tool_max_torque_nm, double(s.torque.norm()));
    report_.tool_max_substeps = std::max(report_.tool_max_substeps, s.substeps);
  }
  return c;
}

std::int64_t ServoLoop::compare_shadow(const Segment& seg, const ForceLaw& law, const Contact& contact,
                                       Contact& other) noexcept {
  ShadowReport& sh = report_.shadow;
  const std::int64_t s0 = now_ns();
  other = shadow_coupling_ ? couple(*shadow_coupling_, seg, law)
          : shadow_proxy_ ? shadow_proxy_->step(seg, law)
                          : shadow_->query(seg, law);
  const std::int64_t shadow_ns = now_ns() - s0;
  shadow_query_hist_.add(shadow_ns);
  if (contact.contact && other.contact) ++sh.both_contact;
  else if (contact.contact) ++sh.drive_only;
  else if (other.contact) ++sh.shadow_only;
  else ++sh.neither;
  if (contact.contact || other.contact) {
    ++sh.contact_ticks;
    const PerceivedDifference felt =
        options_.shadow_is_reference ? perceive(other, contact, options_.perceptual, device_.spec().max_force_n)
                                     : perceive(contact, other, options_.perceptual, device_.spec().max_force_n);
    sh.perceptible += felt.perceptible() ? 1 : 0;
    const float diff = (contact.force - other.force).norm();
    // (clamped: past 1e5 N it only counts as the overflow bin, and llround stays defined)
    if (std::isfinite(diff)) force_diff_hist_.add(std::llround(std::min(double(diff), 1e5) * 1e4));
  }
  if (contact.contact && other.contact) {
    const float na = contact.force.norm(), nb = other.force.norm();
    if (na > 0.f && nb > 0.f && std::isfinite(na) && std::isfinite(nb)) {
      const double c = std::clamp(double(contact.force.dot(other.force)) / (double(na) * nb), -1.0, 1.0);
      angle_hist_.add(std::llround(std::acos(c) * (180.0 / 3.14159265358979323846) * 100.0));
    }
  }
  return shadow_ns;
}

void ServoLoop::record_tick(std::uint64_t tick, const DeviceState& state, const Vec3& force, const Contact& contact,
                            const Contact& other, const ServoSnapshot& snap, LogRecord& rec,
                            ShadowRecord& shadow_rec) noexcept {
  rec.time_s = state.time_s;
  to_array(state.position_m, rec.position_m);
  to_array(force, rec.force_n);
  rec.depth = contact.depth;
  rec.query_ns = snap.query_ns;
  rec.buttons = state.buttons;
  rec.contact = contact.contact;
  rec.safety_flags = snap.safety_flags;
  rec.tick = tick;
  if (recorder_->comparison()) {
    to_array(contact.force, shadow_rec.drive_force_n);
    to_array(contact.normal, shadow_rec.drive_normal);
    to_array(other.force, shadow_rec.shadow_force_n);
    to_array(other.normal, shadow_rec.shadow_normal);
    shadow_rec.shadow_depth = other.depth;
    shadow_rec.shadow_query_ns = snap.shadow_query_ns;
    shadow_rec.shadow_contact = other.contact;
    recorder_->push(rec, &shadow_rec);
  } else {
    recorder_->push(rec);
  }
}

void ServoLoop::finish_report(std::uint64_t tick, std::int64_t first_wake, std::int64_t prev_wake) {
  ServoReport& rep = report_;
  ShadowReport& sh = rep.shadow;
  rep.ticks = tick;
  rep.rate_hz = (prev_wake > first_wake && tick > 1)
                    ? static_cast<double>(period_hist_.count()) / ((prev_wake - first_wake) * 1e-9)
                    : 0.0;
  rep.period = timing_stats(period_hist_);
  rep.period_error = timing_stats(period_error_hist_);
  rep.compute = timing_stats(compute_hist_);
  rep.query = timing_stats(query_hist_);
  rep.safety = safety_.counters();
  if (proxy_) rep.proxy = proxy_->stats();
  if (shadow_proxy_) rep.shadow_proxy = shadow_proxy_->stats();
  if (sh.enabled) {
    sh.query = timing_stats(shadow_query_hist_);
    sh.force_diff_mean_n = force_diff_hist_.mean_ns() * 1e-4;
    sh.force_diff_p50_n = force_diff_hist_.percentile_ns(0.5) * 1e-4;
    sh.force_diff_p99_n = force_diff_hist_.percentile_ns(0.99) * 1e-4;
    sh.force_diff_max_n = force_diff_hist_.max_ns() * 1e-4;
    sh.angle_p50_deg = angle_hist_.percentile_ns(0.5) * 1e-2;
    sh.angle_p99_deg = angle_hist_.percentile_ns(0.99) * 1e-2;
    sh.angle_max_deg = angle_hist_.max_ns() * 1e-2;
  }
  switch (rep.exit) {
    case ServoExit::disconnected:
      rep.exit_message = "device disconnected at tick " + std::to_string(tick) +
                         ": force zeroed, servo loop stopped";
      break;
    case ServoExit::end_of_stream:
      rep.exit_message = "end of replay after " + std::to_string(tick) + " ticks";
      break;
    default:
      rep.exit_message = "stopped after " + std::to_string(tick) + " ticks";
  }
  if (recorder_) {
    rep.log_records = recorder_->written();
    rep.log_dropped = recorder_->dropped();
  }
}

void ServoLoop::publish_tick(std::uint64_t tick, const DeviceState& state, const Segment& seg, const Contact& contact,
                             const Vec3& force, const Contact& other, std::int64_t query_ns, std::int64_t compute_ns,
                             std::int64_t shadow_ns, ServoSnapshot& snap) noexcept {
  snap.tick = tick;
  snap.time_s = state.time_s;
  to_array(state.position_m, snap.position_m);
  to_array(seg.end, snap.tip_model);
  to_array(contact.force, snap.desired_force_n);
  to_array(force, snap.force_n);
  to_array(contact.normal, snap.normal);
  snap.depth = contact.depth;
  snap.buttons = state.buttons;
  snap.safety_flags = safety_.last_flags();
  snap.query_ns = static_cast<std::uint32_t>(query_ns);
  snap.compute_ns = static_cast<std::uint32_t>(compute_ns);
  to_array(other.force, snap.shadow_force_n);
  snap.shadow_query_ns = static_cast<std::uint32_t>(shadow_ns);
  snap.shadow_contact = other.contact;
  snap.contact = contact.contact;
  snap.running = 1;
  snap.emergency_stopped = safety_.emergency_stopped();
  std::copy(safety_.counters().begin(), safety_.counters().end(), snap.safety_counts);
  snapshot_.store(snap);
}

void ServoLoop::run() noexcept {
  ServoReport& rep = report_;
  request_realtime();

  const std::int64_t period = static_cast<std::int64_t>(std::llround(1e9 / options_.rate_hz));
  const std::int64_t spin = static_cast<std::int64_t>(std::max(0.0, options_.spin_s) * 1e9);
  const ForceLaw law = options_.workspace.law();
  const Workspace workspace = options_.workspace;
  DeviceState state;
  ServoSnapshot snap;
  LogRecord rec;
  ShadowRecord shadow_rec;
  ShadowReport& sh = rep.shadow;
  sh.enabled = shadow_ != nullptr;
  std::int64_t deadline = now_ns() + period;
  std::int64_t prev_wake = -1, first_wake = -1;
  // The live window (snapshot rate_hz and period_p99_us): about half a second of ticks.
  const std::uint64_t window_ticks = std::max<std::uint64_t>(1, std::uint64_t(options_.rate_hz / 2.0));
  std::int64_t window_start = -1;
  window_hist_.clear();
  std::uint64_t tick = 0;
  bool estop_applied = false;
  Segment last_segment{}, before_last{};  // the last two ticks' segments (step 2b)
  std::uint64_t queried = 0;
  rep.exit = ServoExit::stopped;

  while (!stop_.load(std::memory_order_acquire)) {
    if (deadline - spin > now_ns()) sleep_until_ns(deadline - spin);
    // The last segment's query in the busy-wait: the lines this tick's query reads were
    // mostly evicted while the thread slept (step 2b).
    // Also when the sleep ended late: those ticks' caches are the coldest, and a warm query
    // costs a fraction of a microsecond (measured on the armadillo: skipping the prime when
    // woken less than 2 or 10 us before the deadline left compute p99 at 2.6-7 us instead of
    // 1.6-2.1; this VM's sleeps often end 40 us or more late).
    if (options_.prime && queried > 0) {
      scene_.prime(last_segment, law);
      // And where the probe is heading: the last tick's motion once more (step 2b). A probe
      // entering new cells would otherwise meet them cold (at 13M triangles the lines a new
      // cell's walk reads are mostly outside every cache).
      const Vec3 step_start = last_segment.start - before_last.start, step_end = last_segment.end - before_last.end;
      if (queried > 1 && !(step_start.isZero(0.f) && step_end.isZero(0.f)))
        scene_.prime(Segment{last_segment.start + step_start, last_segment.end + step_end}, law);
    }
    std::int64_t wake = now_ns();
    while (wake < deadline) {
      cpu_relax();
      wake = now_ns();
    }
    if (first_wake < 0) first_wake = wake;
    if (prev_wake >= 0) {
      const std::int64_t p = wake - prev_wake;
      period_hist_.add(p);
      period_error_hist_.add(p > period ? p - period : period - p);
      window_hist_.add(p);
      if (window_hist_.count() >= window_ticks) {
        snap.rate_hz = static_cast<float>(static_cast<double>(window_hist_.count()) / ((wake - window_start) * 1e-9));
        snap.period_p99_us = static_cast<float>(window_hist_.percentile_ns(0.99) * 1e-3);
        window_hist_.clear();
        window_start = wake;
      }
    } else {
      window_start = wake;
    }
    prev_wake = wake;
    const double lateness_s = (wake - deadline) * 1e-9;

    const DeviceStatus st = device_.read_state(state);
    if (st == DeviceStatus::disconnected || st == DeviceStatus::end_of_stream) {
      device_.write_force(Vec3::Zero());  // best effort; ignored when gone
      rep.exit = st == DeviceStatus::disconnected ? ServoExit::disconnected
                                                  : ServoExit::end_of_stream;
      break;
    }

    const auto recorded = [&](SafetyEvent e) {
      return state.replayed && (state.replayed_flags & (1u << static_cast<unsigned>(e)));
    };
    const bool estop = estop_.load(std::memory_order_acquire) || recorded(SafetyEvent::emergency_stop);
    if (estop != estop_applied) {
      safety_.set_emergency_stop(estop);
      estop_applied = estop;
    }

    const std::int64_t c0 = now_ns();
    const Segment seg = workspace.probe(state.position_m);
    before_last = last_segment;
    last_segment = seg;
    ++queried;
    const Contact contact = coupling_ ? couple(*coupling_, seg, law) : proxy_ ? proxy_->step(seg, law) : scene_.query(seg, law);
    const std::int64_t q1 = now_ns();
    SafetyInput in;
    in.desired_force_n = guard_.apply(contact.force, state.position_m);
    in.position_m = state.position_m;
    // A replay re-applies the recorded timing faults, not its own lateness (see DeviceState).
    in.lateness_s = state.replayed ? (recorded(SafetyEvent::watchdog) ? 1e9 : 0.0) : lateness_s;
    in.device_fault = st == DeviceStatus::fault || recorded(SafetyEvent::device_fault);
    const Vec3 force = safety_.apply(in);
    const std::int64_t c1 = now_ns();

    if (device_.write_force(force) == DeviceStatus::disconnected) {
      rep.exit = ServoExit::disconnected;
      ++tick;
      break;
    }
    compute_hist_.add(c1 - c0);
    query_hist_.add(q1 - c0);

    // The shadow answer, on the same segment, once the force is out.
    Contact other;
    std::int64_t shadow_ns = 0;
    if (shadow_) shadow_ns = compare_shadow(seg, law, contact, other);

    publish_tick(tick, state, seg, contact, force, other, q1 - c0, c1 - c0, shadow_ns, snap);

    if (recorder_) record_tick(tick, state, force, contact, other, snap, rec, shadow_rec);
    ++tick;

    const std::int64_t end = now_ns();
    deadline += period;
    if (end > deadline) {
      ++rep.overruns;
      // Skip deadlines already past instead of bursting to catch up.
      while (deadline + period <= end) {
        deadline += period;
        ++rep.skipped;
      }
    }
  }

  finish_report(tick, first_wake, prev_wake);
  snap.running = 0;
  snap.force_n[0] = snap.force_n[1] = snap.force_n[2] = 0.f;
  snapshot_.store(snap);
  running_.store(false, std::memory_order_release);
}

} // namespace hb
