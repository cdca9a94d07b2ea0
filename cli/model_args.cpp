#include "model_args.h"
#include "errors.h"
#include "mesh/file_hash.h"
#include "mesh/mesh_io.h"
#include "spec_option.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <new>
#include <stdexcept>
#ifdef HB_WITH_VTK
#include "model_load_text.h"
#include "model_loader.h"
#include "model_options_key.h"
#include "model_spec.h"
#include "volume_spec.h"
#endif

namespace hb::cli {

namespace {
// --volume's help and syntax: hb::vtk's, which the window shows too (without VTK the option
// is refused when a model is read).
std::string volume_help() {
#ifdef HB_WITH_VTK
  return hb::vtk::volume_spec_help();
#else
  return "Volumes (needs the VTK pipelines)";
#endif
}
#ifdef HB_WITH_VTK
// A bad spec is a usage error now, before any file is read.
template <class Options>
void check_spec(void (*parse)(const std::string&, Options&), const std::string& spec) {
  Options checked;
  try {
    parse(spec, checked);
  } catch (const InvalidInput& e) {
    throw UsageError(e.what());
  }
}
#endif
std::string volume_syntax() {
#ifdef HB_WITH_VTK
  return hb::vtk::kVolumeSpecSyntax;
#else
  return "iso=V|label=L,smooth=N,triangles=N";
#endif
}
} // namespace

void add_model_options(CLI::App& cmd, ModelArgs& args) {
  const std::string group = "Reading the model";
  cmd.add_option("--unit", args.unit,
                 "Length of one model unit: mm, cm, m, um, in, ft (default: the file's unit, else mm); the model is "
                 "scaled to mm")
      // An unknown unit is a usage error (exit 2), said before any file is read.
      ->check(CLI::Validator(
          [](std::string& unit) -> std::string {
            static const char* const known[] = {"mm", "millimetre", "millimeter", "cm", "centimetre", "centimeter",
                                                "m", "metre", "meter", "um", "micrometre", "micron", "in", "inch",
                                                "ft", "foot"};
            std::string u = unit;
            std::transform(u.begin(), u.end(), u.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            for (const char* k : known)
              if (u == k) return {};
            return "unknown unit '" + unit + "' (use mm, cm, m, um, in or ft)";
          },
          "UNIT"))
      ->group(group);
  cmd.add_option_function<std::string>(
         "--volume",
         [&args](const std::string& spec) {
#ifdef HB_WITH_VTK
           check_spec(hb::vtk::parse_volume_spec, spec);
#endif
           args.volume = spec;
         },
         volume_help())
      ->type_name(volume_syntax())
      ->group(group);
  cmd.add_option_function<std::string>(
         "--cad",
         [&args](const std::string& spec) {
#ifdef HB_WITH_VTK
           check_spec(hb::vtk::parse_cad_spec, spec);
#endif
           args.cad = spec;
         },
         "CAD (STEP, IGES): chordal-mm=D (the tessellation's chordal deviation in mm; default: force-tolerance / "
         "stiffness at the default workspace, clamped to [1e-4, 1e-2] x the solid's diagonal), force-tolerance=N (the force error in N it may cause; default 0.01), "
         "accept-lost-faces (keep a model some of whose faces failed to translate or tessellate; default: refuse "
         "it)")
      ->type_name("chordal-mm=D,force-tolerance=N,accept-lost-faces")
      ->group(group);
}

#ifndef HB_WITH_VTK
namespace {
bool has_model_args(const ModelArgs& a) {
  return !a.volume.empty() || !a.unit.empty() || !a.cad.empty();
}
} // namespace
#endif

TriangleMesh load_mesh(const std::string& path, MeshReadReport* report) { return load_mesh(path, ModelArgs{}, report); }

#ifdef HB_WITH_VTK
hb::vtk::ModelOptions to_model_options(const ModelArgs& args) {
  return hb::vtk::model_options_from_specs(args.unit, args.volume, args.cad);
}
#endif

namespace {
TriangleMesh load_mesh_unguarded(const std::string& path, const ModelArgs& args, MeshReadReport* report);
} // namespace

TriangleMesh load_mesh(const std::string& path, const ModelArgs& args, MeshReadReport* report) {
#ifdef HB_WITH_VTK
  return load_mesh_unguarded(path, args, report);  // hb::vtk::load_model_guarded names a damaged size
#else
  // A size in a damaged file that no allocation can meet names the file, never a bare
  // "std::bad_alloc" or "vector::reserve".
  try {
    return load_mesh_unguarded(path, args, report);
  } catch (const std::bad_alloc&) {
    throw InvalidInput(path + ": out of memory while reading the file (a damaged size in it?)");
  } catch (const std::length_error& e) {
    throw InvalidInput(path + ": the file asks for an impossible size (" + std::string(e.what()) + ")");
  }
#endif
}

namespace {
TriangleMesh load_mesh_unguarded(const std::string& path, const ModelArgs& args, MeshReadReport* report) {
#ifdef HB_WITH_VTK
  const hb::vtk::ModelOptions options = to_model_options(args);
  hb::vtk::LoadedModel model = hb::vtk::load_model_guarded(path, options);
  for (const std::string& w : model.report.warnings) std::cerr << "hapticbox: warning: " << w << "\n";
  const std::string how = hb::vtk::model_load_text(model, options, "; set --volume iso=V");
  if (!how.empty()) std::cerr << "hapticbox: " << path << ": " << how << "\n";
  args.facts = model.facts;
  args.face_ids = model.face_ids;
  if (report) *report = model.report;
  return std::move(model.mesh);
#else
  if (has_model_args(args)) throw UsageError("--volume, --unit and --cad need the VTK pipelines (HB_BUILD_VTK)");
  MeshReadReport local;
  TriangleMesh mesh = read_mesh(path, &local);
  for (const std::string& w : local.warnings) std::cerr << "hapticbox: warning: " << w << "\n";
  if (report) *report = local;
  return mesh;
#endif
}
} // namespace

std::uint64_t hash_model(const std::string& path, const ModelArgs& args) {
#ifdef HB_WITH_VTK
  // The window keys its bakes by the same hash.
  return hb::vtk::model_hash(path, to_model_options(args));
#else
  (void)args;  // without VTK no option shapes the surface (load_mesh refuses them)
  return hb::hash_model(path);
#endif
}

} // namespace hb::cli
