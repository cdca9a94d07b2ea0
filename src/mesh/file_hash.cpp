// hash_file: xxHash64 of a file, read in 1 MB chunks; hash_model: a file, or a folder's files
// in name order, with the loader options mixed in.
#include "mesh/file_hash.h"
#include <cstdio>

#include "errors.h"

#include <xxhash.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <fstream>
#include <memory>
#include <vector>

namespace hb {

namespace fs = std::filesystem;

std::uint64_t hash_file(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(path + ": is a directory, cannot hash");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open for hashing");
  std::unique_ptr<XXH64_state_t, XXH_errorcode (*)(XXH64_state_t*)> state(XXH64_createState(), &XXH64_freeState);
  if (!state || XXH64_reset(state.get(), 0) != XXH_OK) throw IoError(path + ": cannot initialise xxHash");
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), std::streamsize(buf.size()));
    const auto got = in.gcount();
    if (got > 0) XXH64_update(state.get(), buf.data(), std::size_t(got));
  }
  if (in.bad()) throw IoError(path + ": read error while hashing");
  return XXH64_digest(state.get());
}

std::uint64_t hash_model(const std::string& path, const std::string& loader_options) {
  std::error_code ec;
  std::uint64_t h = 0;
  if (fs::is_directory(path, ec)) {
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(path, ec))
      if (e.is_regular_file()) files.push_back(e.path().string());
    if (ec) throw IoError(path + ": cannot list the folder for hashing (" + ec.message() + ")");
    std::sort(files.begin(), files.end());
    for (const std::string& f : files) h = h * 1099511628211ull ^ hash_file(f);
  } else {
    h = hash_file(path);
  }
  // std::hash of the text (libstdc++'s, stable across builds) as the box files written so far
  // recorded it: changing the mixing would make them look baked from another model.
  if (!loader_options.empty()) h ^= std::hash<std::string>{}(loader_options) * 0x9E3779B97F4A7C15ull;
  return h;
}

std::string hash_text(std::uint64_t hash) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash));
  return buf;
}

} // namespace hb
