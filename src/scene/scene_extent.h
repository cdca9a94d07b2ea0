#pragma once
// How large a scene's model is: the bounds of its boxes and the diagonal its workspace is fitted
// to. The command line, the servo loop and the Python module all take a box file's scale here.
#include "scene/box_scene.h"
#include "math/bounds.h"

namespace hb {

/// The axis-aligned bounds of a scene's boxes (the union of their PBB corners), model units;
/// the servo loop centres the device's workspace on them. Empty bounds for no boxes.
Bounds scene_bounds(const BoxScene& scene);

/// The diagonal of the mesh a box file was baked from (SourceInfo::diagonal), or of its
/// boxes' bounds for a file that does not record it (model units; 0 for no boxes).
double model_diagonal(const BoxScene& scene);

} // namespace hb
