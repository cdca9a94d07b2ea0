#pragma once
// What the libFuzzer targets share: a scratch file per process (the readers take paths), the
// check that a rejection carries a message naming the file, and a failure that aborts (so
// libFuzzer records the input as a crash).
#include "errors.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace hb::fuzz {

/// Aborts with `what`: libFuzzer keeps the input that broke an invariant.
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "invariant broken: %s\n", what.c_str());
  std::abort();
}

/// Writes the input to this process's scratch file with extension `ext`; returns its path.
inline std::string write_scratch(const char* ext, const std::uint8_t* data, std::size_t size) {
  const char* dir = std::getenv("TMPDIR");
  const std::string path = std::string(dir && *dir ? dir : "/tmp") + "/hb_fuzz_" + std::to_string(::getpid()) + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) fail("cannot write the scratch file " + path);
  if (size > 0 && std::fwrite(data, 1, size, f) != size) fail("cannot write the scratch file " + path);
  std::fclose(f);
  return path;
}

/// A rejection must say which file and why.
inline void check_rejection(const Error& e, const std::string& path) {
  const std::string what = e.what();
  const std::string name = path.substr(path.find_last_of('/') + 1);
  if (what.find(name) == std::string::npos || what.size() <= path.size() + 2)
    fail("rejection without a message naming the file: '" + what + "'");
}

} // namespace hb::fuzz
