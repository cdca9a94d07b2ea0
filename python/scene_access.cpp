#include "scene_access.h"
#include "contact/workspace.h"
#include "scene/scene_extent.h"

namespace hb::python {

SceneFacts scene_facts(const BoxScene& scene) {
  return {model_diagonal(scene), scene.parts().boxes.size(), answerer_name(answerer(scene))};
}

pybind11::dict scene_info(const BoxScene& scene, const std::string& path) {
  const SceneFacts f = scene_facts(scene);
  const SourceInfo& source = scene.parts().source;
  pybind11::dict d;
  d["path"] = path;
  d["boxes"] = f.boxes;
  d["route"] = f.route;
  d["source_path"] = source.mesh_path;
  d["source_hash"] = source.mesh_hash;
  d["source_triangles"] = source.triangles;
  d["diagonal"] = f.diagonal;
  d["workspace"] = f.diagonal > 0 ? make_workspace(f.diagonal).describe() : std::string();
  return d;
}

std::string scene_repr(const BoxScene& scene, const std::string& path) {
  const SceneFacts f = scene_facts(scene);
  return "<hapticbox.Scene" + (path.empty() ? std::string() : " '" + path + "'") + ": " + std::to_string(f.boxes) +
         " box(es), route " + f.route + ">";
}

} // namespace hb::python
