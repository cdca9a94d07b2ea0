#pragma once
// Third-party readers (VTK's image and XML readers, DICOM, OpenCASCADE, Assimp) run in a child
// process with an address-space limit, a processor-time limit and a wall-clock timeout, so
// that a crash, a hang or a runaway allocation on a damaged file becomes an error message
// naming the file instead of taking the command or the window down.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>

namespace hb::vtk {

/// Limits of a reader run in a child process.
struct ReaderLimits {
  /// false: run the reader in the calling process (no protection; for debugging).
  bool isolate = true;
  /// Wall-clock seconds before the reader is killed (> 0).
  double timeout_s = 120.0;
  /// Megabytes of address space the reader may add to what the process already maps (> 0).
  std::size_t memory_mb = 8192;
  /// The defaults, overridden by the environment: HB_READER_ISOLATION=0 (in-process),
  /// HB_READER_TIMEOUT_S, HB_READER_MEMORY_MB. Throws hb::InvalidInput for a malformed value.
  static ReaderLimits from_environment();
};

/// Where a reader in a child process puts its result: shared memory (a memfd) that the parent
/// maps once the child is done, so that a mesh crosses the process boundary in one copy.
class ResultSink {
public:
  virtual ~ResultSink() = default;
  /// A writable buffer of `bytes` bytes for the result (call at most once).
  virtual char* allocate(std::size_t bytes) = 0;
};

/// Runs `read` (which returns its result serialised as bytes) in a forked child under
/// `limits` and returns those bytes. An hb::IoError or hb::InvalidInput thrown by `read` is
/// rethrown here with the same type and message; std::bad_alloc and any other exception become
/// hb::InvalidInput naming `path` and the cause. A child killed by a signal, by the timeout or
/// by the processor-time limit gives hb::InvalidInput of the form "PATH: the READER reader
/// failed on this file (it crashed: segmentation fault); the file is damaged or not supported".
/// With limits.isolate false, `read` runs in this process (exceptions mapped the same way).
std::string run_isolated(const std::string& path, const std::string& reader, const ReaderLimits& limits,
                         const std::function<std::string()>& read);

/// The same, without copies: `write` (in the child) allocates the result's bytes in shared
/// memory through the sink and fills them; `take` (in this process) reads them in place.
void run_isolated_shared(const std::string& path, const std::string& reader, const ReaderLimits& limits,
                         const std::function<void(ResultSink&)>& write, const std::function<void(std::string_view)>& take);

/// Appends the fields of a serialised result to a string, or writes them at a given address
/// (sized beforehand by a counting writer); native byte order: the bytes never leave the
/// machine.
class ByteWriter {
public:
  ByteWriter() = default;  ///< appends to a string (take()).
  explicit ByteWriter(char* out) : out_(out) {}  ///< writes at `out`.
  static ByteWriter counter() {  ///< writes nothing, counts (size()).
    ByteWriter w;
    w.counting_ = true;
    return w;
  }
  template <class T> void put(const T& v) { raw(&v, sizeof(T)); }
  void put_string(const std::string& s) {
    put<std::uint64_t>(s.size());
    raw(s.data(), s.size());
  }
  template <class T> void put_vector(const T& v) {
    put<std::uint64_t>(v.size());
    raw(v.data(), v.size() * sizeof(typename T::value_type));
  }
  std::size_t size() const { return size_; }
  std::string take() { return std::move(bytes_); }

private:
  void raw(const void* p, std::size_t n) {
    if (n == 0) return;
    if (out_) std::memcpy(out_ + size_, p, n);
    else if (!counting_) bytes_.append(static_cast<const char*>(p), n);
    size_ += n;
  }
  std::string bytes_;
  char* out_ = nullptr;
  bool counting_ = false;
  std::size_t size_ = 0;
};

class ByteReader {
public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  template <class T> T get() {
    T v;
    need(sizeof(T));
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::string get_string() {
    const std::uint64_t n = get<std::uint64_t>();
    need(n);
    std::string s(bytes_.substr(at_, n));
    at_ += n;
    return s;
  }
  template <class T> void get_vector(T& v) {
    const std::uint64_t n = get<std::uint64_t>();
    const std::size_t each = sizeof(typename T::value_type);
    if (n > (bytes_.size() - at_) / each) fail();
    v.resize(n);
    if (n) std::memcpy(static_cast<void*>(v.data()), bytes_.data() + at_, n * each);
    at_ += n * each;
  }

private:
  void need(std::uint64_t n) const {
    if (n > bytes_.size() - at_) fail();
  }
  [[noreturn]] static void fail();
  std::string_view bytes_;
  std::size_t at_ = 0;
};

} // namespace hb::vtk
