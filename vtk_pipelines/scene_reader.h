#pragma once
// Everyday interchange formats (glTF 2.0, 3MF, FBX, Collada) through Assimp, with the unit
// each format declares.
#include "mesh/triangle_mesh.h"
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace hb::vtk {

/// Every triangle of a scene's meshes, node transforms applied, in the file's unit.
struct SceneModel {
  TriangleMesh mesh;
  std::string format;     ///< "glTF", "3MF", "FBX", "Collada".
  /// The file's unit as a name load_model knows ("m", "mm", "cm", "in", ...): glTF is in metres
  /// by its specification, Collada's <unit meter=...> is applied by Assimp (metres), 3MF's
  /// model unit attribute (default millimetre), FBX's UnitScaleFactor (centimetres per unit).
  std::string unit;
  nlohmann::json facts;   ///< meshes, nodes, triangles, unit and where it was read.
  std::vector<std::string> warnings;
};

/// Reads a .gltf, .glb, .3mf, .fbx or .dae file. Points and lines are dropped, polygons
/// triangulated. Throws hb::IoError (missing, empty) or hb::InvalidInput naming the file and
/// Assimp's reason (garbage, no triangles, NaN coordinates).
SceneModel read_scene(const std::string& path);

/// Writes `mesh` (millimetres) with Assimp's exporter in the format of the extension (.gltf,
/// .glb, .3mf, .dae, .fbx), converted to that format's unit as read_scene reads it. For tests
/// and datasets (the formats' round trip). Throws hb::IoError naming the file.
void write_scene(const TriangleMesh& mesh, const std::string& path);

} // namespace hb::vtk
