#pragma once
// How a model became triangles, in one line both front ends show: `hapticbox` on stderr when
// it reads a model, the window in its status bar when it opens one. A volume: its reader,
// dimensions, spacing and iso-value or label; a CAD solid: its faces and chordal deviation; a
// mesh: the unit the file or the options gave. Figures as hb::sig prints them.
#include "model_loader.h"
#include <string>

namespace hb::vtk {

/// The line for `model` as loaded with `options`, e.g. "MetaImage 64 x 64 x 48 voxels, spacing
/// 1 x 1 x 1.5 mm, iso 300 (automatic<iso_hint>): 12345 triangles in mm". `iso_hint` follows
/// "automatic" when the iso-value was chosen by the loader ("; set --volume iso=V" on the
/// command line). Empty for a mesh read at the default unit (nothing to say).
std::string model_load_text(const LoadedModel& model, const ModelOptions& options, const std::string& iso_hint);

} // namespace hb::vtk
