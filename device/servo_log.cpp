// Servo log: reader, SPSC-ring recorder with a writer thread, replay device.
#include "device/servo_log.h"
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace hb {
namespace {

constexpr char magic[8] = {'H', 'B', 'S', 'L', 'O', 'G', '0', '1'};
constexpr std::uint32_t version = 1;

struct Header {
  char magic[8];
  std::uint32_t version;
  std::uint32_t record_size;
  double rate_hz;
  float spec[5];
  std::uint32_t reserved0;
  std::uint8_t reserved[16];
};
static_assert(sizeof(Header) == 64, "64-byte header");

} // namespace

ServoLog read_servo_log(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open servo log: " + std::strerror(errno));
  Header h{};
  in.read(reinterpret_cast<char*>(&h), sizeof h);
  if (in.gcount() != static_cast<std::streamsize>(sizeof h))
    throw InvalidInput(path + ": not a servo log (shorter than its 64-byte header)");
  if (std::memcmp(h.magic, magic, sizeof magic) != 0)
    throw InvalidInput(path + ": not a servo log (bad magic)");
  if (h.version != version)
    throw InvalidInput(path + ": servo log version " + std::to_string(h.version) +
                       " is not supported (expected " + std::to_string(version) + ")");
  if (h.record_size != sizeof(LogRecord))
    throw InvalidInput(path + ": servo log record size " + std::to_string(h.record_size) +
                       " (expected 64)");
  if (!(h.rate_hz >= kMinServoRateHz && h.rate_hz <= kMaxServoRateHz)) {
    char rate[32];
    std::snprintf(rate, sizeof rate, "%g", h.rate_hz);
    throw InvalidInput(path + ": servo log rate " + rate + " Hz is outside [" + std::to_string(int(kMinServoRateHz)) +
                       ", " + std::to_string(int(kMaxServoRateHz)) + "] (corrupt header)");
  }
  ServoLog log;
  log.rate_hz = h.rate_hz;
  log.spec.name = "replay of " + path;
  log.spec.workspace_radius_m = h.spec[0];
  log.spec.max_force_n = h.spec[1];
  log.spec.max_continuous_force_n = h.spec[2];
  log.spec.max_stiffness_n_per_m = h.spec[3];
  log.spec.max_damping_n_s_per_m = h.spec[4];
  // The replay's safety limits are these: a spec no device can have (a negative stiffness
  // would reverse every force, an infinite maximum disable the clamp) is refused.
  if (const std::string why = device_spec_problem(log.spec); !why.empty())
    throw InvalidInput(path + ": servo log device spec: " + why + " (corrupt header)");
  in.seekg(0, std::ios::end);
  const auto bytes = static_cast<std::uint64_t>(in.tellg()) - sizeof h;
  if (bytes % sizeof(LogRecord) != 0)
    throw InvalidInput(path + ": servo log truncated (" + std::to_string(bytes % sizeof(LogRecord)) +
                       " stray bytes after the last whole record)");
  log.records.resize(bytes / sizeof(LogRecord));
  in.seekg(sizeof h);
  in.read(reinterpret_cast<char*>(log.records.data()),
          static_cast<std::streamsize>(log.records.size() * sizeof(LogRecord)));
  if (!in) throw IoError(path + ": read error in servo log");
  return log;
}

LogRecorder::LogRecorder(const std::string& path, double rate_hz, const DeviceSpec& spec,
                         std::size_t capacity)
    : path_(path) {
  std::size_t cap = 1024;
  while (cap < capacity) cap <<= 1;
  ring_.resize(cap);
  mask_ = cap - 1;
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw IoError(path + ": cannot create servo log: " + std::strerror(errno));
  Header h{};
  std::memcpy(h.magic, magic, sizeof magic);
  h.version = version;
  h.record_size = sizeof(LogRecord);
  h.rate_hz = rate_hz;
  h.spec[0] = spec.workspace_radius_m;
  h.spec[1] = spec.max_force_n;
  h.spec[2] = spec.max_continuous_force_n;
  h.spec[3] = spec.max_stiffness_n_per_m;
  h.spec[4] = spec.max_damping_n_s_per_m;
  if (std::fwrite(&h, sizeof h, 1, file_) != 1) {
    std::fclose(file_);
    file_ = nullptr;
    throw IoError(path + ": cannot write servo log header");
  }
  writer_ = std::thread([this] { writer_main(); });
}

LogRecorder::~LogRecorder() {
  try {
    finish();
  } catch (...) {
    // Destructors do not throw; finish() already closed the file.
  }
}

bool LogRecorder::push(const LogRecord& r) noexcept {
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  if (head - tail_.load(std::memory_order_acquire) > mask_) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  ring_[head & mask_] = r;
  head_.store(head + 1, std::memory_order_release);
  return true;
}

void LogRecorder::drain() noexcept {
  std::uint64_t tail = tail_.load(std::memory_order_relaxed);
  const std::uint64_t head = head_.load(std::memory_order_acquire);
  while (tail != head) {
    // Write the contiguous run up to the ring's end in one call.
    const std::size_t start = tail & mask_;
    const std::size_t run = std::min<std::uint64_t>(head - tail, ring_.size() - start);
    if (std::fwrite(&ring_[start], sizeof(LogRecord), run, file_) != run)
      write_failed_.store(true);
    tail += run;
    written_.fetch_add(run, std::memory_order_relaxed);
    tail_.store(tail, std::memory_order_release);
  }
}

void LogRecorder::writer_main() {
  while (!stop_.load(std::memory_order_acquire)) {
    drain();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  drain();
}

void LogRecorder::finish() {
  if (finished_) return;
  finished_ = true;
  stop_.store(true, std::memory_order_release);
  if (writer_.joinable()) writer_.join();
  const bool close_failed = file_ && std::fclose(file_) != 0;
  file_ = nullptr;
  if (write_failed_.load() || close_failed)
    throw IoError(path_ + ": write error in servo log (disk full?)");
}

ReplayDevice::ReplayDevice(const std::string& path) : log_(read_servo_log(path)) {}
ReplayDevice::ReplayDevice(ServoLog log) : log_(std::move(log)) {}

void ReplayDevice::open() {
  if (log_.records.empty()) throw DeviceError(log_.spec.name + ": the log has no records");
  next_ = 0;
}

DeviceStatus ReplayDevice::read_state(DeviceState& out) noexcept {
  if (next_ >= log_.records.size()) return DeviceStatus::end_of_stream;
  const LogRecord& r = log_.records[next_++];
  out.position_m = Vec3(r.position_m[0], r.position_m[1], r.position_m[2]);
  out.buttons = r.buttons;
  out.time_s = r.time_s;
  out.replayed = true;
  out.replayed_flags = r.safety_flags;
  return DeviceStatus::ok;
}

DeviceStatus ReplayDevice::write_force(const Vec3&) noexcept { return DeviceStatus::ok; }

} // namespace hb
