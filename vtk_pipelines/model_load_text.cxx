// model_load_text: the facts load_model recorded (LoadedModel::facts), as one line.
#include "model_load_text.h"
#include "figure_text.h"
#include <sstream>

namespace hb::vtk {

namespace {
// "64 x 64 x 48": a list of figures at 4 significant digits.
std::string figure_list(const nlohmann::json& v, const char* sep) {
  std::string out;
  for (std::size_t i = 0; v.is_array() && i < v.size(); ++i)
    out += (i ? sep : "") + (v[i].is_number() ? sig(v[i].get<double>(), 4) : v[i].dump());
  return out;
}

std::string volume_text(const LoadedModel& model, const ModelOptions& options, const std::string& iso_hint) {
  const nlohmann::json& f = model.facts;
  std::ostringstream o;
  o << model.format << " " << figure_list(f["dimensions"], " x ") << " voxels, spacing "
    << figure_list(f["spacing_mm"], " x ") << " mm, ";
  if (f.contains("label")) o << "label " << f["label"].dump();
  else o << "iso " << sig(f["iso"].get<double>(), 4) << (options.volume.iso ? "" : " (automatic" + iso_hint + ")");
  o << ": " << model.mesh.triangle_count() << " triangles in mm";
  return o.str();
}
} // namespace

std::string model_load_text(const LoadedModel& model, const ModelOptions& options, const std::string& iso_hint) {
  std::ostringstream o;
  if (model.kind == ModelKind::Volume) return volume_text(model, options, iso_hint);
  if (model.kind == ModelKind::Cad) {
    o << model.format << ", " << model.facts.value("faces", 0) << " faces, chordal deviation "
      << model.facts.value("chordal_deviation_mm", 0.0) << " mm: " << model.mesh.triangle_count() << " triangles in mm";
  } else if (model.unit_source != "default (the format has no unit)") {
    o << model.format << ", unit " << model.unit << " (" << model.unit_source << "), scaled to mm";
  }
  return o.str();
}

} // namespace hb::vtk
