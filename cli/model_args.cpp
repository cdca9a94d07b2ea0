#include "model_args.h"
#include "errors.h"
#include "figure_text.h"
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
#include "model_loader.h"
#include "model_options_key.h"
#endif

namespace hb::cli {

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
           parse_spec("--volume", spec,
                      {{"iso", [&args](const std::string& v, const std::string& what) {
                          args.iso = spec_number_or_usage(v, what, -1e30, 1e30);
                        }},
                       {"label", [&args](const std::string& v, const std::string& what) {
                          const double x = spec_number_or_usage(v, what, -9.2e18, 9.2e18);
                          if (x != std::floor(x)) throw UsageError(what + ": '" + v + "' is not a whole number");
                          args.label = long(x);
                        }},
                       number_key("smooth", args.smooth, 0, 1000),
                       number_key("triangles", args.target_triangles, 0, 1e15)});
           if (args.iso && args.label) throw UsageError("--volume: iso and label exclude each other (give one)");
         },
         "Volumes: iso=V (the surface's iso-value in the file's calibrated units, HU for CT; default: the Otsu "
         "threshold, see `info`) or label=L (label maps: the voxels with this label), smooth=N (windowed-sinc "
         "iterations, 0-1000; default 0), triangles=N (decimate to about N; default 0: keep all). Reader limits: "
         "$HB_READER_TIMEOUT_S (default 120 s), $HB_READER_MEMORY_MB (default 8192)")
      ->type_name("iso=V|label=L,smooth=N,triangles=N")
      ->group(group);
  cmd.add_option_function<std::string>(
         "--cad",
         [&args](const std::string& spec) {
           parse_spec("--cad", spec,
                      {{"chordal-mm", [&args](const std::string& v, const std::string& what) {
                          args.chordal_mm = spec_number_or_usage(v, what, 0.0, 1e30);
                        }},
                       {"force-tolerance", [&args](const std::string& v, const std::string& what) {
                          args.force_tolerance_n = spec_number_or_usage(v, what, 1e-30, 1e30);
                        }},
                       flag_key("accept-lost-faces", args.accept_lost_faces)});
         },
         "CAD (STEP, IGES): chordal-mm=D (the tessellation's chordal deviation in mm; default: force-tolerance / "
         "stiffness 500 N/m), force-tolerance=N (the force error in N it may cause; default 0.01), "
         "accept-lost-faces (keep a model some of whose faces failed to translate or tessellate; default: refuse "
         "it)")
      ->type_name("chordal-mm=D,force-tolerance=N,accept-lost-faces")
      ->group(group);
}

#ifndef HB_WITH_VTK
namespace {
bool has_model_args(const ModelArgs& a) {
  return a.iso || a.label || !a.unit.empty() || a.smooth || a.target_triangles || a.chordal_mm > 0 || a.accept_lost_faces;
}
} // namespace
#endif

TriangleMesh load_mesh(const std::string& path, MeshReadReport* report) { return load_mesh(path, ModelArgs{}, report); }

#ifdef HB_WITH_VTK
hb::vtk::ModelOptions to_model_options(const ModelArgs& args) {
  hb::vtk::ModelOptions options;
  options.unit = args.unit;
  options.volume.iso = args.iso;
  options.volume.label = args.label;
  options.volume.smooth_iterations = args.smooth;
  options.volume.target_triangles = args.target_triangles;
  options.cad.chordal_deviation_mm = args.chordal_mm;
  options.cad.force_tolerance_n = args.force_tolerance_n;
  options.cad.accept_lost_faces = args.accept_lost_faces;
  return options;
}
#endif

namespace {
TriangleMesh load_mesh_unguarded(const std::string& path, const ModelArgs& args, MeshReadReport* report);
} // namespace

TriangleMesh load_mesh(const std::string& path, const ModelArgs& args, MeshReadReport* report) {
  // A size in a damaged file that no allocation can meet names the file, never a bare
  // "std::bad_alloc" or "vector::reserve".
  try {
    return load_mesh_unguarded(path, args, report);
  } catch (const std::bad_alloc&) {
    throw InvalidInput(path + ": out of memory while reading the file (a damaged size in it?)");
  } catch (const std::length_error& e) {
    throw InvalidInput(path + ": the file asks for an impossible size (" + std::string(e.what()) + ")");
  }
}

namespace {
TriangleMesh load_mesh_unguarded(const std::string& path, const ModelArgs& args, MeshReadReport* report) {
#ifdef HB_WITH_VTK
  hb::vtk::LoadedModel model = hb::vtk::load_model(path, to_model_options(args));
  for (const std::string& w : model.report.warnings) std::cerr << "hapticbox: warning: " << w << "\n";
  if (model.kind == hb::vtk::ModelKind::Volume) {
    // Figures as the rest of the tool prints them (4 significant digits), not raw doubles.
    const auto list = [](const nlohmann::json& v, const char* sep) {
      std::string out;
      for (std::size_t i = 0; v.is_array() && i < v.size(); ++i)
        out += (i ? sep : "") + (v[i].is_number() ? sig(v[i].get<double>(), 4) : v[i].dump());
      return out;
    };
    std::cerr << "hapticbox: " << path << ": " << model.format << " " << list(model.facts["dimensions"], " x ")
              << " voxels, spacing " << list(model.facts["spacing_mm"], " x ") << " mm, ";
    if (model.facts.contains("label")) std::cerr << "label " << model.facts["label"].dump();
    else std::cerr << "iso " << sig(model.facts["iso"].get<double>(), 4) << (args.iso ? "" : " (automatic; set --iso)");
    std::cerr << ": " << model.mesh.triangle_count() << " triangles in mm\n";
  } else if (model.kind == hb::vtk::ModelKind::Cad) {
    std::cerr << "hapticbox: " << path << ": " << model.format << ", " << model.facts.value("faces", 0) << " faces, chordal deviation "
              << model.facts.value("chordal_deviation_mm", 0.0) << " mm: " << model.mesh.triangle_count() << " triangles in mm\n";
  } else if (model.unit_source != "default (the format has no unit)") {
    std::cerr << "hapticbox: " << path << ": " << model.format << ", unit " << model.unit << " (" << model.unit_source
              << "), scaled to mm\n";
  }
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
  // The window keys its bakes by the same text (hb::vtk::model_options_key).
  return hb::hash_model(path, hb::vtk::model_options_key(to_model_options(args)));
#else
  (void)args;  // without VTK no option shapes the surface (load_mesh refuses them)
  return hb::hash_model(path);
#endif
}

} // namespace hb::cli
