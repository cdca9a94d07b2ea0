// A reader in a child process:
//  1. the parent flushes its output streams and opens an anonymous temporary file (the result
//     channel: a mesh can be far larger than a pipe's buffer) and a pipe (the child writes a
//     mark on it once its result is whole, and its end closes when it dies, which wakes the
//     parent without polling);
//  2. the child lowers its limits (RLIMIT_AS: what it maps now plus the reader's allowance;
//     RLIMIT_CPU: the timeout times the cores, as processor time adds up over threads), sends
//     its standard output to standard error (stdout may be carrying JSON), runs the reader,
//     writes a status byte and the result or the error's text to the file and _exits (no
//     atexit handlers, no destructors of the parent's objects);
//  3. the parent waits for the mark, the pipe's closing or the timeout, kills the child at the
//     timeout, reaps it (after the mark, in the background: the teardown of its address space
//     costs tens of milliseconds), and turns what happened into the result or an error naming
//     the file.
#include "isolated_reader.h"
#include "errors.h"
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
#include <sys/resource.h>
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

// Runs `read`, mapping every exception to (status, text).
char run_mapped(const std::string& path, const std::string& reader, const ReaderLimits& limits,
                const std::function<std::string()>& read, std::string& out) {
  try {
    out = read();
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
    out = failure(path, reader, std::string("it asked for an impossible size: ") + e.what());
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

[[noreturn]] void rethrow(char status, const std::string& text) {
  if (status == kIoError) throw IoError(text);
  throw InvalidInput(text);
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
                        const std::function<std::string()>& read) {
  ::dup2(STDERR_FILENO, STDOUT_FILENO);
  const rlim_t extra = rlim_t(limits.memory_mb) << 20;
  rlimit as{mapped_bytes() + extra, mapped_bytes() + extra};
  ::setrlimit(RLIMIT_AS, &as);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const rlim_t cpu = rlim_t(std::ceil(limits.timeout_s * cores)) + 1;
  rlimit cpu_limit{cpu, cpu + 5};
  ::setrlimit(RLIMIT_CPU, &cpu_limit);
  std::string out;
  const char status = run_mapped(path, reader, limits, read, out);
  const bool ok = write_all(result_fd, &status, 1) && write_all(result_fd, out.data(), out.size());
  // Tell the parent the result is complete: it need not wait for this process's teardown.
  const char done = 'D';
  if (ok) write_all(done_fd, &done, 1);
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
  if (!limits.isolate) {
    std::string out;
    const char status = run_mapped(path, reader, limits, read, out);
    if (status != kOk) rethrow(status, out);
    return out;
  }
  if (!(limits.timeout_s > 0) || limits.memory_mb == 0)
    throw InvalidInput(path + ": the reader's time and memory limits must be > 0");
  std::FILE* result = std::tmpfile();
  if (!result) throw IoError(path + ": cannot create a temporary file for the reader (" + std::strerror(errno) + ")");
  struct Closer {
    std::FILE* f;
    ~Closer() { std::fclose(f); }
  } closer{result};
  const int result_fd = fileno(result);
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
    child(result_fd, done[1], path, reader, limits, read);
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
  // Read the result file.
  std::string bytes;
  if (::lseek(result_fd, 0, SEEK_SET) == 0) {
    char buffer[1 << 16];
    for (;;) {
      const ssize_t n = ::read(result_fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      bytes.append(buffer, std::size_t(n));
    }
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty()) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    throw InvalidInput(failure(path, reader, bytes.empty() ? "it stopped with exit code " + std::to_string(code) + " and no result"
                                                           : "it stopped with exit code " + std::to_string(code)));
  }
  const char s = bytes[0];
  bytes.erase(0, 1);
  if (s != kOk) {
    if (bytes.empty()) bytes = failure(path, reader, "it gave no reason");
    rethrow(s, bytes);
  }
  return bytes;
}

} // namespace hb::vtk
