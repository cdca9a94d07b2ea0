#pragma once
// The spec of a volume's surface as both front ends take it, `--volume iso=V|label=L,smooth=N,
// triangles=N`: one parser and one help text for `hapticbox` and `hapticbox-gui`.
#include "volume_reader.h"
#include <string>

namespace hb::vtk {

/// The option's value as the help shows it.
inline constexpr const char* kVolumeSpecSyntax = "iso=V|label=L,smooth=N,triangles=N";

/// What each key means, with its default and range, and the reader limits' variables.
std::string volume_spec_help();

/// Reads "iso=V,label=L,smooth=N,triangles=N" (any subset, any order) into `options` (keys not
/// given keep their value): iso any finite number (calibrated units, HU for CT), label a whole
/// number, smooth 0-1000 windowed-sinc iterations, triangles a whole number (0: keep all).
/// Throws hb::InvalidInput naming "--volume" and the key: an unknown key (with the known ones),
/// a bad value, iso and label together.
void parse_volume_spec(const std::string& spec, VolumeSurfaceOptions& options);

} // namespace hb::vtk
