#pragma once
// The .hbox file: versioned, checksummed, holds the parameters, the PBBs, the tables and the
// source mesh's hash.
#include "haptic_box/box_scene.h"
#include <string>

namespace hb {

/// Writes `scene` to `path`. Throws hb::IoError.
void save_box_file(const BoxScene& scene, const std::string& path);

/// Loads a box file. Throws hb::IoError (missing, unreadable) or hb::InvalidInput
/// (truncated, corrupt checksum, wrong version, not a box file); messages name the file.
BoxScene load_box_file(const std::string& path);

} // namespace hb
