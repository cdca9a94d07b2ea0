#pragma once
// The text of the loader options that shaped a model's surface, mixed into its hash
// (hb::hash_model's loader_options), so that a box baked at another iso-value, label,
// smoothing, decimation, unit or chordal deviation is never taken for this one. The command
// line and the window both call it: the same options give the same hash.
#include "model_loader.h"
#include <cstdint>
#include <string>

namespace hb::vtk {

/// True when every option that shapes the surface is at its default.
bool model_options_default(const ModelOptions& options);
/// Empty when model_options_default, else "iso=... label=... unit=... smooth=... target=...
/// chordal=... ftol=...".
std::string model_options_key(const ModelOptions& options);
/// hb::hash_model of `path` with model_options_key(options): the hash a box file and the box
/// cache record for a model read with these options.
std::uint64_t model_hash(const std::string& path, const ModelOptions& options);

} // namespace hb::vtk
