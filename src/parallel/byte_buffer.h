#pragma once
// Packing plain values into a byte buffer and reading them back, for the payloads ranks
// exchange (hb::Communicator). Both sides run the same build on the same kind of machine, so
// values travel in the machine's own representation; a short buffer throws. "Plain" means
// copyable as bytes: arithmetic types and structs of them, Eigen's fixed-size vectors too
// (which are not formally trivially copyable, hence no static check).
#include "errors.h"
#include "parallel/communicator.h"
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace hb {

/// Appends trivially copyable values and arrays to a buffer.
class ByteWriter {
public:
  template <class T> void put(const T& value) {
    static_assert(!std::is_pointer_v<T>, "values, not pointers");
    put_bytes(&value, sizeof(T));
  }
  template <class T> void put_vector(const std::vector<T>& values) {
    static_assert(!std::is_pointer_v<T>, "values, not pointers");
    put(std::uint64_t(values.size()));
    put_bytes(values.data(), values.size() * sizeof(T));
  }
  void put_string(const std::string& s) {
    put(std::uint64_t(s.size()));
    put_bytes(s.data(), s.size());
  }
  void put_bytes(const void* data, std::size_t count) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + count);
  }
  void reserve(std::size_t count) { bytes_.reserve(count); }
  Bytes& bytes() { return bytes_; }

private:
  Bytes bytes_;
};

/// Reads what a ByteWriter wrote, in the same order. Throws hb::InvalidInput when the buffer
/// is shorter than what is read (names `what`).
class ByteReader {
public:
  ByteReader(const Bytes& bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}
  template <class T> T get() {
    static_assert(!std::is_pointer_v<T>, "values, not pointers");
    T value;
    get_bytes(&value, sizeof(T));
    return value;
  }
  template <class T> std::vector<T> get_vector() {
    const std::uint64_t count = get<std::uint64_t>();
    if (count > (bytes_.size() - pos_) / sizeof(T)) fail();
    std::vector<T> values(count);
    get_bytes(values.data(), count * sizeof(T));
    return values;
  }
  std::string get_string() {
    const std::uint64_t count = get<std::uint64_t>();
    if (count > bytes_.size() - pos_) fail();
    std::string s(count, '\0');
    get_bytes(s.data(), count);
    return s;
  }
  void get_bytes(void* out, std::size_t count) {
    if (count > bytes_.size() - pos_) fail();
    if (count) std::memcpy(out, bytes_.data() + pos_, count);
    pos_ += count;
  }
  bool at_end() const { return pos_ == bytes_.size(); }

private:
  [[noreturn]] void fail() const { throw InvalidInput(what_ + ": a rank's message is shorter than expected"); }
  const Bytes& bytes_;
  std::string what_;
  std::size_t pos_ = 0;
};

} // namespace hb
