#include "volume_spec.h"
#include "errors.h"
#include "spec_parse.h"
#include <cmath>

namespace hb::vtk {

std::string volume_spec_help() {
  return "Volumes: iso=V (the surface's iso-value in the file's calibrated units, HU for CT; default: the Otsu "
         "threshold, see `info`) or label=L (label maps: the voxels with this label), smooth=N (windowed-sinc "
         "iterations, 0-1000; default 0), triangles=N (decimate to about N; default 0: keep all). Reader limits: "
         "$HB_READER_TIMEOUT_S (default 120 s), $HB_READER_MEMORY_MB (default 8192)";
}

void parse_volume_spec(const std::string& spec, VolumeSurfaceOptions& options) {
  // A whole number in [lo, hi], named by `what` when it is not one.
  const auto whole = [](const std::string& v, const std::string& what, double lo, double hi) {
    const double x = spec_number(v, what, lo, hi);
    if (x != std::floor(x)) throw InvalidInput(what + ": '" + v + "' is not a whole number");
    return x;
  };
  parse_spec_keys("--volume", spec,
             {{"iso", [&](const std::string& v, const std::string& what) { options.iso = spec_number(v, what, -1e30, 1e30); }},
              {"label", [&](const std::string& v, const std::string& what) { options.label = long(whole(v, what, -9.2e18, 9.2e18)); }},
              {"smooth", [&](const std::string& v, const std::string& what) { options.smooth_iterations = int(whole(v, what, 0, 1000)); }},
              {"triangles", [&](const std::string& v, const std::string& what) {
                 options.target_triangles = std::size_t(whole(v, what, 0, 1e15));
               }}});
  if (options.iso && options.label) throw InvalidInput("--volume: iso and label exclude each other (give one)");
}

} // namespace hb::vtk
