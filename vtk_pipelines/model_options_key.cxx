// model_options_key: one text for the options a model was loaded with (see the header).
#include "model_options_key.h"
#include "mesh/file_hash.h"
#include <sstream>

namespace hb::vtk {

bool model_options_default(const ModelOptions& o) {
  return !o.volume.iso && !o.volume.label && o.unit.empty() && o.volume.smooth_iterations == 0 &&
         o.volume.target_triangles == 0 && !(o.cad.chordal_deviation_mm > 0.0);
}

std::string model_options_key(const ModelOptions& o) {
  if (model_options_default(o)) return {};
  std::ostringstream text;
  text << "iso=" << (o.volume.iso ? std::to_string(*o.volume.iso) : "-")
       << " label=" << (o.volume.label ? std::to_string(*o.volume.label) : "-") << " unit=" << o.unit
       << " smooth=" << o.volume.smooth_iterations << " target=" << o.volume.target_triangles
       << " chordal=" << o.cad.chordal_deviation_mm << " ftol=" << o.cad.force_tolerance_n;
  return text.str();
}

std::uint64_t model_hash(const std::string& path, const ModelOptions& options) {
  return hb::hash_model(path, model_options_key(options));
}

} // namespace hb::vtk
