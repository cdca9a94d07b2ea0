#pragma once
// The Workspace of the model a box scene was baked from, as every front end that has only
// the boxes finds it: `hapticbox servo` and the other commands from the box file, the window
// from the boxes its servo thread runs against. The same call, so the same model at the same
// device position gives the same newtons everywhere.
#include "contact/workspace.h"
#include "math/bounds.h"

namespace hb {

class BoxScene;

/// The axis-aligned bounds of a scene's boxes (the union of their PBB corners), model units;
/// the device's workspace is centred on them. Empty bounds for no boxes.
Bounds scene_bounds(const BoxScene& scene);

/// The diagonal of the mesh a box scene was baked from (SourceInfo::diagonal), or of its
/// boxes' bounds for a file that does not record it. Model units.
double model_diagonal(const BoxScene& scene);

/// make_workspace(model_diagonal(scene), options, the centre of scene_bounds(scene)). Throws
/// as make_workspace does (hb::InvalidInput).
Workspace scene_workspace(const BoxScene& scene, const WorkspaceOptions& options = {});

} // namespace hb
