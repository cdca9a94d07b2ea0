// hash_file: xxHash64 of a file, read in 1 MB chunks.
#include "mesh/file_hash.h"

#include "errors.h"

#include <xxhash.h>

#include <filesystem>
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

} // namespace hb
