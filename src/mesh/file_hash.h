#pragma once
// Hashing a model's input: a file's bytes, or a folder's files (a DICOM series), for box
// files, the box cache and reports. One function (hash_model) for every front end, so the
// window and the command line record the same hash for the same input.
#include <cstdint>
#include <string>

namespace hb {

/// 64-bit hash (xxHash64, seed 0) of a file's bytes. Throws hb::IoError (missing, a folder,
/// unreadable).
std::uint64_t hash_file(const std::string& path);

/// The hash a box file records for its source model (hb::SourceInfo::mesh_hash) and the box
/// cache keys by:
///  - a file: hash_file(path);
///  - a folder (a DICOM series): its regular files' hash_file, in name order, folded
///    h = h * 1099511628211 ^ hash_file(f) (sub-folders are not read);
///  - `loader_options` (non-empty): the text of the loader options that shaped the surface
///    (iso-value, label, unit, smoothing, decimation, chordal deviation; empty when they are
///    all at their defaults), mixed in so a box baked at another iso-value is noticed.
/// Throws hb::IoError (missing path, unreadable file).
std::uint64_t hash_model(const std::string& path, const std::string& loader_options = {});

/// A hash as 16 lower-case hex digits ("00ab..."): how reports, box files' JSON and cache
/// names print it.
std::string hash_text(std::uint64_t hash);

} // namespace hb
