// density_range: one pass over a scene's boxes for the smallest and largest m and n.
#include "scene/density_range.h"
#include "scene/box_scene.h"
#include <algorithm>

namespace hb {

DensityRange density_range(const BoxScene& scene) {
  DensityRange r;
  if (scene.parts().boxes.empty()) return r;
  const BoxParams& first = scene.parts().boxes.front().params();
  r.m_min = r.m_max = first.m;
  r.n_min = r.n_max = first.n;
  for (const HapticBox& box : scene.parts().boxes) {
    r.m_min = std::min(r.m_min, box.params().m), r.m_max = std::max(r.m_max, box.params().m);
    r.n_min = std::min(r.n_min, box.params().n), r.n_max = std::max(r.n_max, box.params().n);
  }
  return r;
}

std::string range_text(int lo, int hi) {
  return lo == hi ? std::to_string(lo) : std::to_string(lo) + ".." + std::to_string(hi);
}

std::string density_range_text(const DensityRange& range) {
  return "m=" + range_text(range.m_min, range.m_max) + " n=" + range_text(range.n_min, range.n_max);
}

} // namespace hb
