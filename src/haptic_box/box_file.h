#pragma once
// The .hbox file: versioned, checksummed, holds the parameters, the PBBs, the tables and the
// source mesh's hash.
#include "haptic_box/box_scene.h"
#include <string>

namespace hb {

/// Writes `scene` to `path`. Throws hb::IoError.
void save_box_file(const BoxScene& scene, const std::string& path);

/// Options of load_box_file.
struct LoadOptions {
  /// Hash every table against its stored xxHash3 (reads every page of the file). Off by
  /// default: opening then maps the file and reads only the header and each table's first
  /// page (payload header validation), so a 1 GB box opens in milliseconds and costs only the
  /// pages that queries touch. Corrupt records inside a payload then read as misses (the
  /// decoders never read out of bounds); `hapticbox info --verify` checks everything.
  bool verify = false;
};

/// Loads a box file (versions 1 and 2). Throws hb::IoError (missing, unreadable) or
/// hb::InvalidInput (truncated, corrupt checksum, corrupt compressed payload header, wrong
/// version, not a box file); messages name the file and the cause.
BoxScene load_box_file(const std::string& path, const LoadOptions& options = {});

} // namespace hb
