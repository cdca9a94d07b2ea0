#pragma once
// Binary servo log, one fixed-size record per tick at full rate, and its recorder.
//
// File layout (little-endian, native IEEE floats):
//   header, 64 bytes: magic "HBSLOG01", u32 version (1 or 2), u32 record size (64 or 128),
//                     f64 rate_hz, f32 x5 device spec (workspace radius, max force, max
//                     continuous force, max stiffness, max damping), u32 rendered answer
//                     (version 2: 0 the box drove the device, 1 the exact answer; 0 in
//                     version 1), 16 bytes reserved.
//   records: version 1, 64 bytes each (LogRecord); version 2 (a comparison recording,
//            `servo BOX --exact MESH`), 128 bytes each: LogRecord then ShadowRecord.
#include "device/haptic_device.h"
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace hb {

/// One servo tick as logged.
struct LogRecord {
  double time_s = 0;            ///< device time, s.
  float position_m[3] = {};     ///< device position, m.
  float force_n[3] = {};        ///< force written to the device (after safety), N.
  float depth = 0;              ///< contact depth, model units (0 without contact).
  std::uint32_t query_ns = 0;   ///< duration of the contact query, ns.
  std::uint32_t buttons = 0;
  std::uint8_t contact = 0;     ///< 1 when the query reported a contact.
  std::uint8_t reserved[3] = {};
  std::uint32_t safety_flags = 0;  ///< SafetyFilter::last_flags() of the tick.
  std::uint64_t tick = 0;
};
static_assert(sizeof(LogRecord) == 64, "LogRecord is a 64-byte on-disk record");
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "log format is little-endian");

/// Which answer drove the device in a comparison recording (the other ran in shadow).
enum class RenderedAnswer : std::uint32_t { box = 0, exact = 1 };
const char* to_string(RenderedAnswer a) noexcept;

/// The rest of a tick in a comparison recording: the driving answer before the energy guard
/// and safety, and the shadow answer, queried on the same segment with the same law in the
/// same tick (it never reaches the device).
struct ShadowRecord {
  float drive_force_n[3] = {};   ///< the driving query's force, before guard and safety, N.
  float drive_normal[3] = {};
  float shadow_force_n[3] = {};  ///< the shadow query's force, N.
  float shadow_normal[3] = {};
  float shadow_depth = 0;        ///< model units (0 without contact).
  std::uint32_t shadow_query_ns = 0;
  std::uint8_t shadow_contact = 0;
  std::uint8_t reserved[7] = {};
};
static_assert(sizeof(ShadowRecord) == 64, "ShadowRecord is a 64-byte on-disk record");

/// Content of a log file.
struct ServoLog {
  double rate_hz = 1000.0;
  DeviceSpec spec;
  std::vector<LogRecord> records;
  /// Comparison recordings (version 2): one per record, and which answer drove the device.
  std::vector<ShadowRecord> shadow;
  RenderedAnswer rendered = RenderedAnswer::box;
  bool comparison = false;  ///< a version 2 file: `shadow` has one entry per record.
};

/// Reads a whole log. Throws IoError (missing, unreadable) or InvalidInput (not a servo log,
/// wrong version, a record size not the version's, truncated, a rate outside [1, 20000] Hz, a
/// device spec no device can have (see device_spec_problem), an unknown rendered answer);
/// messages name the file.
ServoLog read_servo_log(const std::string& path);

/// Writes `log` as CSV, one row a tick (position, force sent, the driving query's contact,
/// depth and time; in a comparison recording also box_* and exact_* columns: force before
/// safety, normal, contact, depth, query time of each). Throws IoError naming the file.
void write_servo_log_csv(const ServoLog& log, const std::string& path);

/// Writes records to a log file from the servo thread without blocking it: push() copies into
/// a preallocated single-producer/single-consumer ring; a writer thread drains it to disk.
/// When the ring is full the record is dropped and counted (never blocks the loop).
class LogRecorder {
public:
  /// Creates `path` (truncating) and writes the header. Throws IoError naming the file.
  LogRecorder(const std::string& path, double rate_hz, const DeviceSpec& spec,
              std::size_t capacity = 1u << 16);
  /// A comparison recording (version 2): every push carries a ShadowRecord.
  LogRecorder(const std::string& path, double rate_hz, const DeviceSpec& spec, RenderedAnswer rendered,
              std::size_t capacity = 1u << 16);
  ~LogRecorder();
  LogRecorder(const LogRecorder&) = delete;
  LogRecorder& operator=(const LogRecorder&) = delete;

  /// Servo-thread side: noexcept, allocation-free. Returns false when the record was dropped.
  /// `shadow` is stored in a comparison recording (zeros when null) and ignored otherwise.
  bool push(const LogRecord& r, const ShadowRecord* shadow = nullptr) noexcept;
  bool comparison() const noexcept { return !shadow_ring_.empty(); }

  /// Drains what is left, flushes and closes. Idempotent. Throws IoError when a write failed.
  void finish();

  std::uint64_t written() const noexcept { return written_.load(); }
  std::uint64_t dropped() const noexcept { return dropped_.load(); }
  const std::string& path() const { return path_; }

private:
  void open(double rate_hz, const DeviceSpec& spec, std::size_t capacity, bool comparison, RenderedAnswer rendered);
  void drain() noexcept;
  void writer_main();

  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<LogRecord> ring_;
  std::vector<ShadowRecord> shadow_ring_;  ///< same slots as ring_; empty in version 1.
  std::size_t mask_;
  std::atomic<std::uint64_t> head_{0};  ///< next slot the producer writes.
  std::atomic<std::uint64_t> tail_{0};  ///< next slot the consumer reads.
  std::atomic<std::uint64_t> written_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<bool> stop_{false};
  std::atomic<bool> write_failed_{false};
  std::thread writer_;
  bool finished_ = false;
};

/// Plays a log back as a device: each read_state() returns the next record's position, buttons
/// and time; after the last record it returns DeviceStatus::end_of_stream. The spec is the one
/// stored in the log, so safety limits are the same as in the recorded run.
class ReplayDevice final : public HapticDevice {
public:
  /// Reads the log now (throws like read_servo_log).
  explicit ReplayDevice(const std::string& path);
  explicit ReplayDevice(ServoLog log);

  const DeviceSpec& spec() const noexcept override { return log_.spec; }
  void open() override;
  void close() noexcept override {}
  DeviceStatus read_state(DeviceState& out) noexcept override;
  DeviceStatus write_force(const Vec3& force_n) noexcept override;

  const ServoLog& log() const { return log_; }
  std::size_t position() const noexcept { return next_; }

private:
  ServoLog log_;
  std::size_t next_ = 0;
};

} // namespace hb
