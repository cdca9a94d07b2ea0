#pragma once
// Hashing a file's bytes, for box files, caches and reports.
#include <cstdint>
#include <string>

namespace hb {

/// 64-bit hash (xxHash64, seed 0) of a file's bytes. Throws hb::IoError (missing, a folder,
/// unreadable).
std::uint64_t hash_file(const std::string& path);

} // namespace hb
