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
constexpr std::uint32_t version = 1;             ///< plain recordings
constexpr std::uint32_t comparison_version = 2;  ///< with a ShadowRecord per tick

struct Header {
  char magic[8];
  std::uint32_t version;
  std::uint32_t record_size;
  double rate_hz;
  float spec[5];
  std::uint32_t rendered;  ///< version 2: RenderedAnswer; 0 in version 1.
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
  if (h.version != version && h.version != comparison_version)
    throw InvalidInput(path + ": servo log version " + std::to_string(h.version) +
                       " is not supported (expected " + std::to_string(version) + " or " +
                       std::to_string(comparison_version) + ")");
  const bool comparison = h.version == comparison_version;
  const std::size_t record_size = sizeof(LogRecord) + (comparison ? sizeof(ShadowRecord) : 0);
  if (h.record_size != record_size)
    throw InvalidInput(path + ": servo log record size " + std::to_string(h.record_size) + " (expected " +
                       std::to_string(record_size) + " in version " + std::to_string(h.version) + ")");
  if (h.rendered > (comparison ? 1u : 0u))
    throw InvalidInput(path + ": servo log rendered answer " + std::to_string(h.rendered) + " is not " +
                       (comparison ? "0 (box) or 1 (exact)" : "0 in version 1") + " (corrupt header)");
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
  log.comparison = comparison;
  log.rendered = static_cast<RenderedAnswer>(h.rendered);
  in.seekg(0, std::ios::end);
  const auto bytes = static_cast<std::uint64_t>(in.tellg()) - sizeof h;
  if (bytes % record_size != 0)
    throw InvalidInput(path + ": servo log truncated (" + std::to_string(bytes % record_size) +
                       " stray bytes after the last whole record)");
  const std::size_t n = bytes / record_size;
  log.records.resize(n);
  in.seekg(sizeof h);
  if (!comparison) {
    in.read(reinterpret_cast<char*>(log.records.data()), static_cast<std::streamsize>(n * sizeof(LogRecord)));
  } else {
    log.shadow.resize(n);
    for (std::size_t i = 0; i < n && in; ++i) {
      in.read(reinterpret_cast<char*>(&log.records[i]), sizeof(LogRecord));
      in.read(reinterpret_cast<char*>(&log.shadow[i]), sizeof(ShadowRecord));
    }
  }
  if (!in) throw IoError(path + ": read error in servo log");
  return log;
}

const char* to_string(RenderedAnswer a) noexcept { return a == RenderedAnswer::exact ? "exact" : "box"; }

void write_servo_log_csv(const ServoLog& log, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw IoError(path + ": cannot create the servo CSV: " + std::strerror(errno));
  std::fprintf(f, "tick,time_s,x_m,y_m,z_m,fx_n,fy_n,fz_n,contact,depth,query_ns,buttons,safety_flags");
  if (log.comparison) {
    std::fprintf(f, ",rendered");
    for (const char* who : {"box", "exact"})
      std::fprintf(f, ",%s_fx_n,%s_fy_n,%s_fz_n,%s_nx,%s_ny,%s_nz,%s_contact,%s_depth,%s_query_ns", who, who, who, who,
                   who, who, who, who, who);
  }
  std::fprintf(f, "\n");
  for (std::size_t i = 0; i < log.records.size(); ++i) {
    const LogRecord& r = log.records[i];
    std::fprintf(f, "%llu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%u,%.9g,%u,%u,%u", static_cast<unsigned long long>(r.tick),
                 r.time_s, r.position_m[0], r.position_m[1], r.position_m[2], r.force_n[0], r.force_n[1], r.force_n[2],
                 unsigned(r.contact), r.depth, r.query_ns, r.buttons, r.safety_flags);
    if (log.comparison) {
      const ShadowRecord& s = log.shadow[i];
      const auto answer = [&](bool drive) {
        const float* fo = drive ? s.drive_force_n : s.shadow_force_n;
        const float* no = drive ? s.drive_normal : s.shadow_normal;
        std::fprintf(f, ",%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%u,%.9g,%u", fo[0], fo[1], fo[2], no[0], no[1], no[2],
                     unsigned(drive ? r.contact : s.shadow_contact), drive ? r.depth : s.shadow_depth,
                     drive ? r.query_ns : s.shadow_query_ns);
      };
      std::fprintf(f, ",%s", to_string(log.rendered));
      const bool box_drives = log.rendered == RenderedAnswer::box;
      answer(box_drives);   // box columns
      answer(!box_drives);  // exact columns
    }
    std::fprintf(f, "\n");
  }
  const bool failed = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || failed) throw IoError(path + ": write error in the servo CSV (disk full?)");
}

LogRecorder::LogRecorder(const std::string& path, double rate_hz, const DeviceSpec& spec,
                         std::size_t capacity)
    : path_(path) {
  open(rate_hz, spec, capacity, false, RenderedAnswer::box);
}

LogRecorder::LogRecorder(const std::string& path, double rate_hz, const DeviceSpec& spec, RenderedAnswer rendered,
                         std::size_t capacity)
    : path_(path) {
  open(rate_hz, spec, capacity, true, rendered);
}

void LogRecorder::open(double rate_hz, const DeviceSpec& spec, std::size_t capacity, bool comparison,
                       RenderedAnswer rendered) {
  std::size_t cap = 1024;
  while (cap < capacity) cap <<= 1;
  ring_.resize(cap);
  if (comparison) shadow_ring_.resize(cap);
  mask_ = cap - 1;
  file_ = std::fopen(path_.c_str(), "wb");
  if (!file_) throw IoError(path_ + ": cannot create servo log: " + std::strerror(errno));
  Header h{};
  std::memcpy(h.magic, magic, sizeof magic);
  h.version = comparison ? comparison_version : version;
  h.record_size = sizeof(LogRecord) + (comparison ? sizeof(ShadowRecord) : 0);
  h.rate_hz = rate_hz;
  h.spec[0] = spec.workspace_radius_m;
  h.spec[1] = spec.max_force_n;
  h.spec[2] = spec.max_continuous_force_n;
  h.spec[3] = spec.max_stiffness_n_per_m;
  h.spec[4] = spec.max_damping_n_s_per_m;
  h.rendered = comparison ? static_cast<std::uint32_t>(rendered) : 0u;
  if (std::fwrite(&h, sizeof h, 1, file_) != 1) {
    std::fclose(file_);
    file_ = nullptr;
    throw IoError(path_ + ": cannot write servo log header");
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

bool LogRecorder::push(const LogRecord& r, const ShadowRecord* shadow) noexcept {
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  if (head - tail_.load(std::memory_order_acquire) > mask_) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  ring_[head & mask_] = r;
  if (!shadow_ring_.empty()) shadow_ring_[head & mask_] = shadow ? *shadow : ShadowRecord{};
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
    if (shadow_ring_.empty()) {
      if (std::fwrite(&ring_[start], sizeof(LogRecord), run, file_) != run) write_failed_.store(true);
    } else {
      for (std::size_t i = start; i < start + run; ++i)
        if (std::fwrite(&ring_[i], sizeof(LogRecord), 1, file_) != 1 ||
            std::fwrite(&shadow_ring_[i], sizeof(ShadowRecord), 1, file_) != 1)
          write_failed_.store(true);
    }
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
