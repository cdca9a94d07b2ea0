#pragma once
// Everything the Python module asks a BoxScene besides its answers (ContactQuery::query_many),
// in one file: the one place to follow when BoxScene's accessors move.
#include "scene/box_scene.h"
#include <pybind11/pybind11.h>
#include <string>

namespace hb::python {

/// The facts of a scene the bindings need.
struct SceneFacts {
  double diagonal = 0.0;  ///< the model diagonal its workspace is fitted to (hb::model_diagonal).
  std::size_t boxes = 0;
  std::string route;      ///< the route that answers (hb::answerer_name of hb::answerer).
};
SceneFacts scene_facts(const BoxScene& scene);

/// Scene.info(): boxes, route, source (path, hash, triangles, diagonal), default workspace.
pybind11::dict scene_info(const BoxScene& scene, const std::string& path);
/// "<hapticbox.Scene 'arm.hbox': 12 boxes, route embree>".
std::string scene_repr(const BoxScene& scene, const std::string& path);

} // namespace hb::python
