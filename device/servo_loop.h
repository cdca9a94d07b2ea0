#pragma once
// The servo thread: fixed rate on absolute deadlines; each tick reads the device, queries the
// scene, applies safety and writes the force, allocating and locking nothing. The latest state
// is published through a seqlock snapshot that a GUI reads at display rate.
#include "device/energy_guard.h"
#include "device/haptic_device.h"
#include "device/safety.h"
#include "device/seqlock.h"
#include "device/timing_histogram.h"
#include "contact/contact.h"
#include "contact/god_object.h"
#include "perception/perceptible.h"
#include "contact/workspace.h"
#include "tool/tool_coupling.h"
#include <memory>
#include <atomic>
#include <optional>
#include <string>
#include <thread>

namespace hb {

class LogRecorder;
struct LogRecord;
struct ShadowRecord;

/// Options of ServoLoop.
struct ServoOptions {
  double rate_hz = 1000.0;          ///< tick rate, Hz, in (0, 20000].
  bool request_realtime = true;     ///< ask for SCHED_FIFO; the report says whether granted.
  int realtime_priority = 80;       ///< SCHED_FIFO priority, 1..99.
  double spin_s = 50e-6;            ///< sleep until deadline - spin, then busy-wait, s (0 = none).
  bool prime = true;                ///< at the start of the busy-wait, ask the scene's prime()
                                    ///< with the last tick's segment and, when the probe moved,
                                    ///< that segment moved once more (answers discarded), so the
                                    ///< tick's query finds the scene's data in cache; no effect
                                    ///< on any answer (`servo --no-prime`: the figures without).
  /// The model at the device: each tick's probe (Workspace::probe of the device position) and
  /// its force law (Workspace::law); see limit_stiffness. `hapticbox servo` and the window
  /// both take hb::scene_workspace of the boxes they run against.
  Workspace workspace;
  bool limit_stiffness = true;      ///< lower the stiffness so the stiffness felt at the device
                                    ///< stays <= spec.max_stiffness_n_per_m, for any stylus
                                    ///< tilt up to 75 degrees (felt_stiffness_factor: 1 for
                                    ///< the normal depth law, 3.86 along the segment).
  EnergyGuardOptions energy_guard;  ///< passivity observer / controller, off by default.
  SafetyOptions safety;
  /// How each tick's answer becomes the force (`servo --law`): ContactLaw::penalty, the force
  /// law on the scene's answer (stateless; the default for now), or ContactLaw::proxy, a
  /// GodObject kept by the loop (Zilles and Salisbury 1995; contact/god_object.h) fed each
  /// tick's segment over the scene, and a second one over the shadow (set_shadow), so both
  /// answers are rendered by the same law. Either way the force then goes through the energy
  /// guard and the safety filter. The stiffness limit is the penalty law's (the proxy falls
  /// back to the penalty answer when it finds no constraint).
  ContactLaw contact_law = ContactLaw::penalty;
  /// With a shadow (set_shadow): what a hand tells apart (ShadowReport::perceptible), and which
  /// answer is the reference the JND is taken of (true: the shadow, e.g. exact beside a box
  /// that drives; false: the driving answer).
  PerceptualThresholds perceptual;
  bool shadow_is_reference = true;
  GodObjectOptions proxy;           ///< with ContactLaw::proxy (clearance > 0, max_queries >= 1).
  /// A tool with volume (`servo --tool`): the mapped device position is the tool's centre and
  /// the force is its virtual coupling's (ToolCoupling; a second one over the shadow), in place
  /// of the probe segment and the contact law. nullptr: the point probe.
  std::shared_ptr<const ToolShape> tool;
  ToolCouplingOptions coupling;
};

/// Latest servo state, published every tick (trivially copyable for the seqlock).
struct ServoSnapshot {
  std::uint64_t tick = 0;
  double time_s = 0;
  float position_m[3] = {};      ///< device position.
  float tip_model[3] = {};       ///< probe tip in model units.
  float desired_force_n[3] = {}; ///< from the query, before safety.
  float force_n[3] = {};         ///< written to the device.
  float normal[3] = {};
  float depth = 0;
  std::uint32_t buttons = 0;
  std::uint32_t safety_flags = 0;
  std::uint32_t query_ns = 0;
  std::uint32_t compute_ns = 0;
  /// Measured over the last window of about half a second of ticks (0 until the first ends):
  /// the tick rate, Hz, and the 99th percentile of the wake-to-wake period, us.
  float rate_hz = 0;
  float period_p99_us = 0;
  float shadow_force_n[3] = {};  ///< the shadow answer's force (set_shadow), else 0.
  std::uint32_t shadow_query_ns = 0;
  std::uint8_t shadow_contact = 0;
  std::uint8_t contact = 0;
  std::uint8_t running = 0;
  std::uint8_t emergency_stopped = 0;
  std::uint64_t safety_counts[safety_event_count] = {};
};

/// Why the loop stopped.
enum class ServoExit : std::uint8_t { not_started, stopped, end_of_stream, disconnected };
const char* to_string(ServoExit e) noexcept;

/// Percentiles of one histogram, microseconds.
struct TimingStats {
  double p50_us = 0, p99_us = 0, p999_us = 0, max_us = 0, mean_us = 0;
  std::uint64_t count = 0;
};
TimingStats timing_stats(const TimingHistogram& h);

/// The driving answer against the shadow answer (ServoLoop::set_shadow), both computed on the
/// same segment with the same law in every tick, compared before the energy guard and safety.
struct ShadowReport {
  bool enabled = false;
  TimingStats query;                     ///< the shadow query alone.
  std::uint64_t both_contact = 0, drive_only = 0, shadow_only = 0, neither = 0;  ///< ticks
  /// |F_drive - F_shadow|, N, over the ticks where either has a contact (0.1 mN bins).
  double force_diff_mean_n = 0, force_diff_p50_n = 0, force_diff_p99_n = 0, force_diff_max_n = 0;
  /// Angle between the two forces, degrees, over the ticks where both have a contact (0.01 degree bins).
  double angle_p50_deg = 0, angle_p99_deg = 0, angle_max_deg = 0;
  /// Ticks whose two answers a hand would tell apart (hb::perceive at the loop's thresholds,
  /// the reference answer's force as the JND's base, forces clamped to the device's maximum),
  /// over the ticks where either has a contact (`contact_ticks`).
  std::uint64_t perceptible = 0, contact_ticks = 0;
};

/// What a run measured; complete after stop().
struct ServoReport {
  std::uint64_t ticks = 0;
  double nominal_rate_hz = 0;
  double rate_hz = 0;               ///< measured: (ticks - 1) / (last wake - first wake).
  TimingStats period;               ///< wake-to-wake.
  TimingStats period_error;         ///< |period - nominal|.
  TimingStats compute;              ///< query + safety.
  TimingStats query;                ///< the contact law's answer alone (the proxy: all its queries).
  std::uint64_t overruns = 0;       ///< ticks that ended after the next tick's deadline.
  std::uint64_t skipped = 0;        ///< deadlines skipped to resynchronise after an overrun.
  bool realtime_requested = false;
  bool realtime_granted = false;
  std::string realtime_message;     ///< why not granted (strerror), or the policy granted.
  float stiffness_n_per_m = 0;      ///< law stiffness used (after limiting).
  bool stiffness_limited = false;
  SafetyCounters safety{};
  ServoExit exit = ServoExit::not_started;
  std::string exit_message;
  std::uint64_t log_records = 0, log_dropped = 0;
  ShadowReport shadow;
  ContactLaw contact_law = ContactLaw::penalty;  ///< the law the run used.
  /// With ContactLaw::proxy: what the driving answer's proxy and the shadow's did (zero else).
  GodObjectStats proxy, shadow_proxy;
  /// With a tool: the largest torque its contact put on the simulated tool (shown and logged,
  /// not rendered by a 3-DOF device), N m, and the most sub-steps a tick took.
  double tool_max_torque_nm = 0;
  int tool_max_substeps = 0;
};

/// Runs the servo loop on its own thread. The device and the scene must outlive the loop.
/// Each tick's force comes from `scene` by options.contact_law (penalty or a proxy).
class ServoLoop {
public:
  ServoLoop(HapticDevice& device, const ContactQuery& scene, ServoOptions options = {});
  ~ServoLoop();  ///< stops.
  ServoLoop(const ServoLoop&) = delete;
  ServoLoop& operator=(const ServoLoop&) = delete;

  /// Records every tick to `recorder` (not owned; set before start; finish it after stop).
  void set_recorder(LogRecorder* recorder) noexcept { recorder_ = recorder; }
  /// Also queries `shadow` (not owned, outlives the loop; set before start) on every tick's
  /// segment, after the force is written: its answer never reaches the device. It is compared
  /// with the driving answer (ServoReport::shadow, ServoSnapshot) and logged when the recorder
  /// is a comparison recording. `servo BOX --exact MESH` drives with one, shadows the other.
  void set_shadow(const ContactQuery* shadow) noexcept { shadow_ = shadow; }

  /// Opens the device (throws its DeviceError) and starts the thread. Throws std::logic_error
  /// when already running, InvalidInput for bad options.
  void start();
  /// Asks the thread to stop, joins it, zeroes force and closes the device. Idempotent.
  void stop();
  /// True while the thread runs (false after end of stream or disconnect, before stop()).
  bool running() const noexcept { return running_.load(std::memory_order_acquire); }

  /// Latches zero force until clear_emergency_stop() (any thread, lock-free).
  void emergency_stop() noexcept { estop_.store(true, std::memory_order_release); }
  void clear_emergency_stop() noexcept { estop_.store(false, std::memory_order_release); }

  /// Latest published state (any thread, lock-free, at any rate).
  ServoSnapshot snapshot() const noexcept { return snapshot_.load(); }

  /// The run's measurements; call after stop().
  const ServoReport& report() const noexcept { return report_; }
  /// The options actually used (stiffness limited).
  const ServoOptions& options() const noexcept { return options_; }

private:
  void run() noexcept;
  // The steps of run() off the tick's critical path: the thread's scheduling, the shadow
  // answer once the force is out (returns its ns), the tick's log record, the final report.
  void request_realtime() noexcept;
  std::int64_t compare_shadow(const Segment& seg, const ForceLaw& law, const Contact& contact, Contact& other) noexcept;
  void record_tick(std::uint64_t tick, const DeviceState& state, const Vec3& force, const Contact& contact,
                   const Contact& other, const ServoSnapshot& snap, LogRecord& rec, ShadowRecord& shadow_rec) noexcept;
  void finish_report(std::uint64_t tick, std::int64_t first_wake, std::int64_t prev_wake);
  /// The tick's snapshot for the window (seqlock), after the force is out.
  void publish_tick(std::uint64_t tick, const DeviceState& state, const Segment& seg, const Contact& contact,
                    const Vec3& force, const Contact& other, std::int64_t query_ns, std::int64_t compute_ns,
                    std::int64_t shadow_ns, ServoSnapshot& snap) noexcept;

  HapticDevice& device_;
  const ContactQuery& scene_;
  ServoOptions options_;
  LogRecorder* recorder_ = nullptr;
  const ContactQuery* shadow_ = nullptr;
  // ContactLaw::proxy: the driving answer's proxy and the shadow's, made afresh by start()
  // (in place: the tick allocates nothing).
  std::optional<GodObject> proxy_, shadow_proxy_;
  std::optional<ToolCoupling> coupling_, shadow_coupling_;
  // The tick's answer through the tool's coupling, as a contact (force, its direction, the
  // simulated tool's centre as the point).
  Contact couple(ToolCoupling& coupling, const Segment& seg, const ForceLaw& law) noexcept;
  SafetyFilter safety_;
  EnergyGuard guard_;
  TimingHistogram period_hist_, period_error_hist_, compute_hist_, query_hist_;
  TimingHistogram window_hist_;  ///< periods of the current live window (snapshot rate, p99).
  // The shadow comparison (the histogram counts integers: ns, 0.1 mN, 0.01 degree).
  TimingHistogram shadow_query_hist_, force_diff_hist_, angle_hist_;
  Seqlock<ServoSnapshot> snapshot_;
  ServoReport report_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> running_{false};
  std::atomic<bool> estop_{false};
  std::thread thread_;
  bool opened_ = false;
};

} // namespace hb
