#pragma once
// How large a scene's model is and where it sits at the device: the bounds of its boxes, the
// diagonal its workspace is fitted to, and that Workspace. Every front end that has only the
// boxes (the commands from a box file, the window's servo thread, the Python module) takes it
// here, so the same model at the same device position gives the same newtons everywhere.
#include "contact/workspace.h"
#include "scene/box_scene.h"
#include "math/bounds.h"

namespace hb {

/// The axis-aligned bounds of a scene's boxes (the union of their PBB corners), model units;
/// the servo loop centres the device's workspace on them. Empty bounds for no boxes.
Bounds scene_bounds(const BoxScene& scene);

/// The diagonal of the mesh a box file was baked from (SourceInfo::diagonal), or of its
/// boxes' bounds for a file that does not record it (model units; 0 for no boxes).
double model_diagonal(const BoxScene& scene);

/// make_workspace(model_diagonal(scene), options, the centre of scene_bounds(scene)). Throws
/// as make_workspace does (hb::InvalidInput).
Workspace scene_workspace(const BoxScene& scene, const WorkspaceOptions& options = {});

} // namespace hb
