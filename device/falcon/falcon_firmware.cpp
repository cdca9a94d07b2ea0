#include "device/falcon/falcon_firmware.h"
#include "device/device_error.h"
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace hb {
namespace {

std::string hex(const std::uint8_t* p, std::size_t n) {
  std::string s;
  char buf[8];
  for (std::size_t i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof buf, i ? " 0x%02X" : "0x%02X", p[i]);
    s += buf;
  }
  return n ? s : "nothing";
}

/// A step failed in a way a retry may fix.
struct StepFailure {
  bool timeout;
  std::string what;
};

void write_all(FalconTransport& t, const std::uint8_t* d, std::size_t n, int timeout_ms,
               const char* step) {
  const IoResult r = t.write(d, n, timeout_ms);
  if (r.status == IoStatus::disconnected)
    throw DeviceDisconnected(t.description() + ": disconnected during " + step);
  if (r.status != IoStatus::ok || r.bytes != n)
    throw StepFailure{r.status == IoStatus::timeout, std::string(step) + ": write failed"};
}

/// Reads exactly n bytes or until a read times out; returns what was read.
std::size_t read_upto(FalconTransport& t, std::uint8_t* d, std::size_t n, int timeout_ms,
                      const char* step) {
  std::size_t got = 0;
  while (got < n) {
    const IoResult r = t.read(d + got, n - got, timeout_ms);
    if (r.status == IoStatus::disconnected)
      throw DeviceDisconnected(t.description() + ": disconnected during " + step);
    if (r.status == IoStatus::error)
      throw StepFailure{false, std::string(step) + ": read error"};
    if (r.bytes == 0) break;
    got += r.bytes;
  }
  return got;
}

void attempt(FalconTransport& t, const std::vector<std::uint8_t>& fw, const FirmwareOptions& o) {
  t.purge();
  t.set_latency_timer(16);
  t.set_baud_rate(falcon_bootloader_baud);
  t.set_line_8n1();
  t.set_flow_control_none();
  t.set_rts(false);
  t.set_dtr(false);
  t.set_dtr(true);

  static const std::uint8_t hs1[3] = {0x0A, 0x43, 0x0D};
  static const std::uint8_t hs1_reply[4] = {0x0A, 0x44, 0x2C, 0x0D};
  std::string last = "no answer";
  bool ok = false, answered = false;
  for (int i = 0; i < o.handshake_attempts && !ok; ++i) {
    write_all(t, hs1, 3, o.timeout_ms, "handshake 1");
    std::uint8_t buf[16];
    const std::size_t n = read_upto(t, buf, 5, o.timeout_ms, "handshake 1");
    if (n == 0) continue;
    answered = true;
    const std::uint8_t* p = buf;
    std::size_t m = n;
    if (m == 5 && p[0] == 0x00) ++p, --m;
    ok = m == 4 && std::memcmp(p, hs1_reply, 4) == 0;
    if (!ok) last = "wrong echo (got " + hex(buf, n) + ", expected " + hex(hs1_reply, 4) + ")";
  }
  if (!ok)
    throw StepFailure{!answered, "handshake 1 at 9600 baud: " + last + " after " +
                                     std::to_string(o.handshake_attempts) + " tries"};

  t.set_dtr(false);
  t.set_baud_rate(falcon_firmware_load_baud);
  const std::uint8_t a = 'A';
  write_all(t, &a, 1, o.timeout_ms, "handshake 2");
  std::uint8_t echo = 0;
  const std::size_t n = read_upto(t, &echo, 1, o.timeout_ms, "handshake 2");
  if (n == 0) throw StepFailure{true, "handshake 2: no answer"};
  if (echo != 'A') throw StepFailure{false, "handshake 2: wrong echo (got " + hex(&echo, 1) + ", expected 0x41)"};

  const std::size_t bs = o.block_size ? o.block_size : 128;
  const std::size_t blocks = (fw.size() + bs - 1) / bs;
  std::vector<std::uint8_t> back(bs);
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t off = b * bs, len = std::min(bs, fw.size() - off);
    const std::string step = "firmware block " + std::to_string(b + 1) + " of " +
                             std::to_string(blocks) + " (bytes " + std::to_string(off) + ".." +
                             std::to_string(off + len - 1) + ")";
    write_all(t, fw.data() + off, len, o.timeout_ms, step.c_str());
    const std::size_t got = read_upto(t, back.data(), len, o.timeout_ms, step.c_str());
    if (got < len)
      throw StepFailure{got == 0, step + ": echo short (" + std::to_string(got) + " of " +
                                      std::to_string(len) + " bytes)"};
    for (std::size_t i = 0; i < len; ++i)
      if (back[i] != fw[off + i])
        throw StepFailure{false, step + ": echo differs at byte " + std::to_string(off + i) +
                                     " (got " + hex(&back[i], 1) + ", sent " +
                                     hex(&fw[off + i], 1) + ")"};
  }
}

} // namespace

std::vector<std::uint8_t> read_firmware_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw IoError(path + ": cannot open Falcon firmware: " + std::strerror(errno) +
                  " (the firmware is not shipped: set its path, e.g. --firmware test_firmware.bin)");
  std::vector<std::uint8_t> fw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (fw.empty()) throw InvalidInput(path + ": Falcon firmware file is empty");
  return fw;
}

void load_falcon_firmware(FalconTransport& t, const std::vector<std::uint8_t>& fw,
                          const FirmwareOptions& o) {
  if (fw.empty()) throw InvalidInput("Falcon firmware is empty");
  std::ostringstream diag;
  bool all_timeouts = true;
  const int attempts = std::max(1, o.attempts);
  for (int i = 1; i <= attempts; ++i) {
    try {
      attempt(t, fw, o);
      return;
    } catch (const StepFailure& f) {
      diag << (i > 1 ? "; " : "") << "attempt " << i << ": " << f.what;
      all_timeouts = all_timeouts && f.timeout;
    }
  }
  const std::string msg = t.description() + ": firmware load failed: " + diag.str();
  if (all_timeouts) throw DeviceTimeout(msg + " (is the Falcon powered? its power supply must be plugged in)");
  throw DeviceProtocolError(msg);
}

void set_falcon_normal_mode(FalconTransport& t) {
  t.set_latency_timer(1);
  t.set_baud_rate(falcon_normal_baud);
  t.purge();
}

} // namespace hb
