#include "model_spec.h"
#include "errors.h"
#include "spec_parse.h"
#include "volume_spec.h"
#include <new>
#include <stdexcept>

namespace hb::vtk {

void parse_cad_spec(const std::string& spec, CadOptions& cad) {
  const auto flag = [&cad](const std::string& v, const std::string& what) {
    if (v.empty() || v == "1" || v == "on" || v == "yes") cad.accept_lost_faces = true;
    else if (v == "0" || v == "off" || v == "no") cad.accept_lost_faces = false;
    else throw InvalidInput(what + ": '" + v + "' is not on or off");
  };
  parse_spec_keys("--cad", spec,
                  {{"chordal-mm", [&cad](const std::string& v, const std::string& what) {
                      cad.chordal_deviation_mm = spec_number(v, what, 0.0, 1e30);
                    }},
                   {"force-tolerance", [&cad](const std::string& v, const std::string& what) {
                      cad.force_tolerance_n = spec_number(v, what, 1e-30, 1e30);
                    }},
                   {"accept-lost-faces", flag}});
}

ModelOptions model_options_from_specs(const std::string& unit, const std::string& volume, const std::string& cad) {
  ModelOptions options;
  if (!unit.empty()) mm_per_unit(unit);  // an unknown unit is named now, before any file is read
  options.unit = unit;
  parse_volume_spec(volume, options.volume);
  parse_cad_spec(cad, options.cad);
  return options;
}

LoadedModel load_model_guarded(const std::string& path, const ModelOptions& options) {
  try {
    return load_model(path, options);
  } catch (const std::bad_alloc&) {
    throw InvalidInput(path + ": out of memory while reading the file (a damaged size in it?)");
  } catch (const std::length_error& e) {
    throw InvalidInput(path + ": the file asks for an impossible size (" + std::string(e.what()) + ")");
  }
}

} // namespace hb::vtk
