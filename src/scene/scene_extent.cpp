#include "scene/scene_extent.h"
#include <limits>

namespace hb {

Bounds scene_bounds(const BoxScene& scene) {
  Bounds b;
  if (scene.parts().boxes.empty()) return b;
  b.min = Vec3::Constant(std::numeric_limits<float>::max());
  b.max = -b.min;
  for (const auto& box : scene.parts().boxes) {
    const Obb& o = box.obb();
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner = o.to_world(Vec3((c & 1) ? o.half.x() : -o.half.x(), (c & 2) ? o.half.y() : -o.half.y(),
                                          (c & 4) ? o.half.z() : -o.half.z()));
      b.min = b.min.cwiseMin(corner);
      b.max = b.max.cwiseMax(corner);
    }
  }
  return b;
}

double model_diagonal(const BoxScene& scene) {
  if (scene.parts().source.diagonal > 0.f) return scene.parts().source.diagonal;
  return scene.parts().boxes.empty() ? 0.0 : double(scene_bounds(scene).diagonal());
}

Workspace scene_workspace(const BoxScene& scene, const WorkspaceOptions& options) {
  const Bounds b = scene_bounds(scene);
  return make_workspace(model_diagonal(scene), options, 0.5f * (b.min + b.max));
}

} // namespace hb
