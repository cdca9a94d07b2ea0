#include "parallel/communicator.h"
#include "parallel/byte_buffer.h"
#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace hb {

std::vector<double> Communicator::all_values(double value) {
  ByteWriter w;
  w.put(value);
  std::vector<double> out;
  for (const Bytes& b : all_gather(w.bytes())) {
    ByteReader r(b, "all_values");
    out.push_back(r.get<double>());
  }
  return out;
}

double Communicator::sum(double value) {
  if (size() == 1) return value;
  double total = 0.0;
  for (double v : all_values(value)) total += v;  // rank order: the same sum on every run
  return total;
}

std::uint64_t Communicator::sum(std::uint64_t value) {
  if (size() == 1) return value;
  ByteWriter w;
  w.put(value);
  std::uint64_t total = 0;
  for (const Bytes& b : all_gather(w.bytes())) {
    ByteReader r(b, "sum");
    total += r.get<std::uint64_t>();
  }
  return total;
}

double Communicator::max(double value) {
  if (size() == 1) return value;
  const std::vector<double> values = all_values(value);
  return *std::max_element(values.begin(), values.end());
}

void SerialCommunicator::abort(const std::string& message, int code) {
  std::fprintf(stderr, "%s\n", message.c_str());
  std::fflush(stderr);
  std::_Exit(code == 0 ? 1 : code);
}

Communicator& serial_communicator() {
  static SerialCommunicator serial;
  return serial;
}

} // namespace hb
