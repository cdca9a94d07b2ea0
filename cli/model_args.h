#pragma once
// How a command reads its model: --unit, --volume and --cad, and the loader every command that
// takes a mesh goes through (so it also takes a volume, a CAD solid or a glTF/3MF/FBX/Collada
// scene), with the hash a box file records for its source.
#include "mesh/triangle_mesh.h"
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hb {
struct MeshReadReport;
}

#ifdef HB_WITH_VTK
#include "model_loader.h"
#endif

namespace hb::cli {

/// How a model file becomes a mesh (--unit, --volume, --cad; see hb::vtk::ModelOptions).
/// Every command that takes a mesh takes these, so it also takes a volume, a CAD solid or a
/// glTF/3MF/FBX/Collada scene.
struct ModelArgs {
  std::string unit;
  std::string volume;  ///< --volume's spec as given (hb::vtk::parse_volume_spec reads it).
  /// --cad's spec as given (hb::vtk::parse_cad_spec reads it: chordal-mm, force-tolerance,
  /// accept-lost-faces, which keeps a model some of whose faces failed to translate).
  std::string cad;
  /// Filled by load_mesh: what the loader found (format, unit, volume/CAD facts) and, for CAD
  /// solids, the face of each triangle (used by --pieces faces).
  mutable nlohmann::json facts;
  mutable std::vector<std::uint32_t> face_ids;
};

#ifdef HB_WITH_VTK
/// The loader's options for `args` (for the commands that run vtkHapticBoxMeshReader).
hb::vtk::ModelOptions to_model_options(const ModelArgs& args);
#endif

/// Adds --unit, --volume (iso, label, smooth, triangles: hb::vtk::parse_volume_spec, the window's
/// --volume too) and --cad (chordal-mm, force-tolerance, accept-lost-faces). The readers' limits come from $HB_READER_TIMEOUT_S and $HB_READER_MEMORY_MB.
void add_model_options(CLI::App& cmd, ModelArgs& args);

/// Reads a model (mesh, volume, CAD, scene; in millimetres), printing the reader's warnings to
/// stderr, and on stderr one line saying how a volume or CAD file became triangles.
TriangleMesh load_mesh(const std::string& path, const ModelArgs& args = {}, MeshReadReport* report = nullptr);
/// Reads a mesh with the default model options.
TriangleMesh load_mesh(const std::string& path, MeshReadReport* report);

/// hb::hash_model (mesh/file_hash.h) of `path` with the loader options of `args` (their text
/// when any differs from its default): the hash a box file records for its source.
std::uint64_t hash_model(const std::string& path, const ModelArgs& args = {});

} // namespace hb::cli
