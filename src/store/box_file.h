#pragma once
// The .hbox file: versioned, checksummed, holds the parameters, the PBBs, the tables, the
// triangle ids and surface of refined boxes, the piece ids and the source mesh's hash.
#include "scene/box_scene.h"
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
  /// Copy the file into anonymous memory advised for transparent huge pages
  /// (MADV_HUGEPAGE, 2 MB aligned) instead of querying the page-cache mapping. For boxes
  /// opened to be queried at speed: random queries touch four hemi-cubes far apart in a
  /// table of hundreds of MB, and with 4 KB pages most of them miss the TLB as well as the
  /// cache. Costs one read of the whole file at opening and its size in private memory;
  /// when huge pages are unavailable the copy still works (4 KB pages).
  bool huge_pages = false;
};

/// Loads a box file (versions 1 to 7; the format is described in box_file_format.h).
/// Throws hb::IoError (missing, unreadable) or hb::InvalidInput (truncated, corrupt checksum,
/// corrupt compressed payload header, wrong version, not a box file); messages name the file
/// and the cause.
BoxScene load_box_file(const std::string& path, const LoadOptions& options = {});

} // namespace hb
