// A reader in a child process:
//  1. the parent flushes its output streams and creates a memfd (the result channel: shared
//     memory, as a mesh can be far larger than a pipe's buffer; the child sizes it and writes
//     the result in place, the parent maps it: one copy across, and no file system) and a pipe
//     (the child writes a mark on it once its result is whole, and its end closes when it
//     dies, which wakes the parent without polling);
//  2. the child lowers its limits (RLIMIT_AS: what it maps now plus the reader's allowance;
//     RLIMIT_CPU: the timeout times the cores, as processor time adds up over threads), sends
//     its standard output to standard error (stdout may be carrying JSON), runs the reader,
//     which allocates its result in the memfd (a status byte first) or leaves the error's
//     text there, and _exits (no atexit handlers, no destructors of the parent's objects);
//  3. the parent waits for the mark, the pipe's closing or the timeout, kills the child at the
//     timeout, reaps it (after the mark, in the background: the teardown of its address space
//     costs tens of milliseconds), and turns what happened into the result or an error naming
//     the file (escaped and cut to a readable length: formats/quoted_text.h).
#include "isolated_reader.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <iostream>
#include <new>
#include <poll.h>
#include <sstream>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace hb::vtk {

namespace {

// Status byte at the start of the result file.
constexpr char kOk = 'K', kIoError = 'O', kInvalid = 'I', kOther = 'E', kNoMemory = 'M';

std::string signal_text(int sig) {
  switch (sig) {
    case SIGSEGV: return "it crashed: segmentation fault";
    case SIGBUS: return "it crashed: bus error";
    case SIGFPE: return "it crashed: arithmetic exception";
    case SIGILL: return "it crashed: illegal instruction";
    case SIGABRT: return "it crashed: aborted";
    case SIGXCPU: return "it used up its processor-time limit";
    default: return std::string("it was killed by signal ") + std::to_string(sig) + " (" + strsignal(sig) + ")";
  }
}

std::string failure(const std::string& path, const std::string& reader, const std::string& why,
                    const std::string& ending = "the file is damaged or not supported") {
  return path + ": the " + reader + " reader failed on this file (" + why + "); " + ending;
}

// Runs `run`, mapping every exception to (status, text); kOk when it returns.
char run_mapped(const std::string& path, const std::string& reader, const ReaderLimits& limits, const std::function<void()>& run,
                std::string& out) {
  try {
    run();
    return kOk;
  } catch (const IoError& e) {
    out = e.what();
    return kIoError;
  } catch (const InvalidInput& e) {
    out = e.what();
    return kInvalid;
  } catch (const std::bad_alloc&) {
    out = failure(path, reader,
                  limits.isolate ? "it ran out of memory: it asked for more than the " + std::to_string(limits.memory_mb) + " MB allowed"
                                 : std::string("it ran out of memory"),
                  "the file is damaged, or needs more memory (HB_READER_MEMORY_MB)");
    return kNoMemory;
  } catch (const std::length_error& e) {
    // The library's text ("vector::_M_default_append") names its own code, not the file's.
    const std::string what = e.what();
    out = what.rfind(path, 0) == 0 ? what
                                   : failure(path, reader, "a count or size in the file asked it for an array longer than any memory holds");
    return kInvalid;
  } catch (const std::exception& e) {
    const std::string what = e.what();
    out = what.rfind(path, 0) == 0 ? what : failure(path, reader, "it threw: " + (what.empty() ? std::string("an exception") : what));
    return kOther;
  } catch (...) {
    out = failure(path, reader, "it threw an unknown exception");
    return kOther;
  }
}

// In this process: the result in a string.
class StringSink : public ResultSink {
public:
  char* allocate(std::size_t bytes) override {
    data.assign(bytes, '\0');
    return data.data();
  }
  std::string data;
};

// In the child: the result in the memfd, after its status byte.
class MemfdSink : public ResultSink {
public:
  explicit MemfdSink(int fd) : fd_(fd) {}
  ~MemfdSink() override {
    if (map_) ::munmap(map_, size_);
  }
  char* allocate(std::size_t bytes) override {
    if (map_) throw std::logic_error("ResultSink::allocate called twice");
    size_ = bytes + 1;
    if (::ftruncate(fd_, off_t(size_)) != 0) throw std::bad_alloc();
    // MAP_POPULATE: the pages in one go, not a fault per page as they are written.
    void* m = ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_POPULATE, fd_, 0);
    if (m == MAP_FAILED) throw std::bad_alloc();
    map_ = static_cast<char*>(m);
    return map_ + 1;
  }
  // The status byte (the result is in place) or, for an error, the status and the text.
  bool finish(char status, const std::string& text) {
    if (status == kOk && map_) {
      map_[0] = kOk;
      return true;
    }
    if (map_) {
      ::munmap(map_, size_);
      map_ = nullptr;
    }
    if (::ftruncate(fd_, 0) != 0) return false;
    std::string all(1, status);
    all += text;
    std::size_t at = 0;
    while (at < all.size()) {
      const ssize_t w = ::pwrite(fd_, all.data() + at, all.size() - at, off_t(at));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) return false;
      at += std::size_t(w);
    }
    return true;
  }

private:
  int fd_;
  char* map_ = nullptr;
  std::size_t size_ = 0;
};

// The reader's error, as a person can read it: a library's text (or ours quoting the file) may
// hold raw bytes or run to kilobytes.
[[noreturn]] void rethrow(char status, const std::string& text) {
  if (status == kIoError) throw IoError(readable_message(text));
  throw InvalidInput(readable_message(text));
}

bool write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += w;
    n -= std::size_t(w);
  }
  return true;
}

std::size_t mapped_bytes() {
  // /proc/self/statm: total program size in pages.
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  unsigned long pages = 0;
  if (std::fscanf(f, "%lu", &pages) != 1) pages = 0;
  std::fclose(f);
  return std::size_t(pages) * std::size_t(sysconf(_SC_PAGESIZE));
}

[[noreturn]] void child(int result_fd, int done_fd, const std::string& path, const std::string& reader, const ReaderLimits& limits,
                        const std::function<void(ResultSink&)>& write) {
  ::dup2(STDERR_FILENO, STDOUT_FILENO);
  const rlim_t extra = rlim_t(limits.memory_mb) << 20;
  rlimit as{mapped_bytes() + extra, mapped_bytes() + extra};
  ::setrlimit(RLIMIT_AS, &as);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const rlim_t cpu = rlim_t(std::ceil(limits.timeout_s * cores)) + 1;
  rlimit cpu_limit{cpu, cpu + 5};
  ::setrlimit(RLIMIT_CPU, &cpu_limit);
  std::string error;
  MemfdSink sink(result_fd);
  const char status = run_mapped(path, reader, limits, [&] { write(sink); }, error);
  bool ok = sink.finish(status, error);
  // Tell the parent the result is complete: it need not wait for this process's teardown.
  const char done = 'D';
  if (ok) ok = write_all(done_fd, &done, 1);
  ::_exit(ok ? 0 : 3);
}

} // namespace

void ByteReader::fail() { throw InvalidInput("the reader's child process returned a malformed result"); }

ReaderLimits ReaderLimits::from_environment() {
  ReaderLimits l;
  auto number = [](const char* name, double lo, double hi) -> double {
    const char* v = std::getenv(name);
    if (!v || !*v) return -1;
    char* end = nullptr;
    const double d = std::strtod(v, &end);
    if (*end || !(d >= lo && d <= hi))
      throw InvalidInput(std::string(name) + "=" + v + ": must be a number from " + std::to_string(lo) + " to " + std::to_string(hi));
    return d;
  };
  if (const char* v = std::getenv("HB_READER_ISOLATION"); v && std::string(v) == "0") l.isolate = false;
  if (double t = number("HB_READER_TIMEOUT_S", 0.1, 1e6); t > 0) l.timeout_s = t;
  if (double m = number("HB_READER_MEMORY_MB", 16, 1 << 24); m > 0) l.memory_mb = std::size_t(m);
  return l;
}

std::string run_isolated(const std::string& path, const std::string& reader, const ReaderLimits& limits,
                         const std::function<std::string()>& read) {
  std::string out;
  run_isolated_shared(
      path, reader, limits,
      [&](ResultSink& sink) {
        const std::string bytes = read();
        char* at = sink.allocate(bytes.size());
        if (!bytes.empty()) std::memcpy(at, bytes.data(), bytes.size());
      },
      [&](std::string_view bytes) { out.assign(bytes); });
  return out;
}

void run_isolated_shared(const std::string& path, const std::string& reader, const ReaderLimits& limits,
                         const std::function<void(ResultSink&)>& write, const std::function<void(std::string_view)>& take) {
  if (!limits.isolate) {
    StringSink sink;
    std::string error;
    const char status = run_mapped(path, reader, limits, [&] { write(sink); }, error);
    if (status != kOk) rethrow(status, error);
    take(sink.data);
    return;
  }
  if (!(limits.timeout_s > 0) || limits.memory_mb == 0)
    throw InvalidInput(path + ": the reader's time and memory limits must be > 0");
  const int result_fd = ::memfd_create("hb-reader-result", MFD_CLOEXEC);
  if (result_fd < 0) throw IoError(path + ": cannot create shared memory for the reader (" + std::strerror(errno) + ")");
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{result_fd};
  int done[2];
  if (::pipe2(done, O_CLOEXEC) != 0) throw IoError(path + ": cannot create a pipe for the reader (" + std::strerror(errno) + ")");
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(done[0]);
    ::close(done[1]);
    throw IoError(path + ": cannot start a process for the reader (" + std::strerror(err) + ")");
  }
  if (pid == 0) {
    ::close(done[0]);
    child(result_fd, done[1], path, reader, limits, write);
  }
  ::close(done[1]);
  // Wait for the child's end of the pipe to close (it exited or died), at most timeout_s.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(limits.timeout_s);
  bool timed_out = false, completed = false;
  int status = 0;
  for (;;) {
    const pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      timed_out = true;
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      break;
    }
    pollfd p{done[0], POLLIN, 0};
    // At most 100 ms per round: another process forked meanwhile may hold a copy of the pipe.
    const int r = ::poll(&p, 1, int(std::min<long long>(left, 100)));
    if (r > 0) {
      char c = 0;
      const ssize_t n = ::read(done[0], &c, 1);
      if (n == 1 && c == 'D') {  // the result is whole; the child is exiting
        completed = true;
        break;
      }
      if (n <= 0) {  // closed without the mark: the child died; reap it
        while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        break;
      }
    }
  }
  ::close(done[0]);
  if (completed) {
    // Reap the exiting child without waiting for its address space to be torn down.
    if (::waitpid(pid, &status, WNOHANG) != pid)
      std::thread([pid] {
        int s = 0;
        while (::waitpid(pid, &s, 0) < 0 && errno == EINTR) {
        }
      }).detach();
    status = 0;
  }
  if (timed_out) {
    std::ostringstream why;
    why << "it was still running after " << limits.timeout_s << " s and was stopped";
    throw InvalidInput(failure(path, reader, why.str(),
                               "the file is damaged, or needs more time (HB_READER_TIMEOUT_S)"));
  }
  if (WIFSIGNALED(status)) {
    std::string why = signal_text(WTERMSIG(status));
    if (WTERMSIG(status) == SIGKILL) why = "it was killed: out of memory or past its processor-time limit";
    if (WTERMSIG(status) == SIGKILL || WTERMSIG(status) == SIGXCPU)
      throw InvalidInput(failure(path, reader, why, "the file is damaged, or needs more time or memory (HB_READER_TIMEOUT_S, HB_READER_MEMORY_MB)"));
    throw InvalidInput(failure(path, reader, why));
  }
  // The result: mapped, read in place.
  struct stat st {};
  const std::size_t size = ::fstat(result_fd, &st) == 0 ? std::size_t(st.st_size) : 0;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || size == 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    throw InvalidInput(failure(path, reader, size == 0 ? "it stopped with exit code " + std::to_string(code) + " and no result"
                                                       : "it stopped with exit code " + std::to_string(code)));
  }
  void* m = ::mmap(nullptr, size, PROT_READ, MAP_SHARED | MAP_POPULATE, result_fd, 0);
  if (m == MAP_FAILED) throw IoError(path + ": cannot map the reader's result (" + std::strerror(errno) + ")");
  struct Unmap {
    void* m;
    std::size_t n;
    ~Unmap() { ::munmap(m, n); }
  } unmap{m, size};
  const char* bytes = static_cast<const char*>(m);
  if (bytes[0] != kOk) {
    std::string text(bytes + 1, size - 1);
    if (text.empty()) text = failure(path, reader, "it gave no reason");
    rethrow(bytes[0], text);
  }
  take(std::string_view(bytes + 1, size - 1));
}

} // namespace hb::vtk
