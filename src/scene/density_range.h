#pragma once
// The densities of a scene's boxes. Each box has its own m and n (the budget chooses them per
// piece), so a scene is described by their range, never by its first box's. `bake`, `info`,
// the report, the error field's provenance and the window's bake panel all take it from here.
#include <string>

namespace hb {

class BoxScene;

/// The smallest and largest m (position points per PBB face edge) and n (directional points
/// per sub-block face edge) over a scene's boxes.
struct DensityRange {
  int m_min = 0, m_max = 0, n_min = 0, n_max = 0;
};

/// The range over `scene`'s boxes; all zero for a scene without boxes.
DensityRange density_range(const BoxScene& scene);

/// "8..15", or "8" when `lo` == `hi`.
std::string range_text(int lo, int hi);

/// "m=8..15 n=6".
std::string density_range_text(const DensityRange& range);

} // namespace hb
