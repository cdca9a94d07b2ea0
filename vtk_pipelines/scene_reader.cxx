// Scenes through Assimp:
//  1. Assimp reads the file with triangulation, node transforms baked into the vertices
//     (PreTransformVertices), identical vertices joined, points and lines dropped;
//  2. every mesh's triangles go into one core mesh;
//  3. the unit: glTF metres (its specification), Collada metres (Assimp applies <unit meter>),
//     FBX from the UnitScaleFactor metadata (centimetres per unit), 3MF from the model's unit
//     attribute, read here from the zip (Assimp does not expose it).
// Each file is checked before Assimp opens it (scene_file_checks.h).
#include "scene_reader.h"
#include "scene_file_checks.h"
#include "string_util.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/DefaultLogger.hpp>
#include <assimp/config.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

namespace hb::vtk {

namespace {

namespace fs = std::filesystem;

std::string format_of(const std::string& ext) {
  if (ext == ".gltf" || ext == ".glb") return "glTF";
  if (ext == ".3mf") return "3MF";
  if (ext == ".fbx") return "FBX";
  if (ext == ".dae") return "Collada";
  return ext;
}

std::string extension(const std::string& path) { return lower(fs::path(path).extension().string()); }

// Assimp's reason, as a person can read it: its binary FBX tokenizer ends a message with the
// offending type code as a raw byte (often unprintable), and some failures give no text at all.
std::string assimp_reason(const std::string& text) {
  std::string t = text;
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  if (t.empty()) return "it gave no reason (the file is damaged or a kind it does not read)";
  // A standard container's length error names the library's code, not the file's.
  if (t.rfind("vector::", 0) == 0 || t.find("_M_") != std::string::npos)
    return "a count or size in the file asked it for an array longer than any memory holds";
  const std::size_t colon = t.rfind(": ");
  if (colon != std::string::npos && colon + 3 == t.size() && !std::isprint(static_cast<unsigned char>(t.back()))) {
    static const char hex[] = "0123456789ABCDEF";
    const unsigned char c = static_cast<unsigned char>(t.back());
    t = t.substr(0, colon) + ": byte 0x" + hex[c >> 4] + hex[c & 15] + " (not a code the format defines: the file is damaged)";
  }
  return quoted_text(t, 1000);
}

} // namespace

SceneModel read_scene(const std::string& path) {
  if (!fs::exists(path)) throw IoError(path + ": no such file");
  if (!std::ifstream(path).good()) throw IoError(path + ": cannot open the file");
  if (fs::file_size(path) == 0) throw IoError(path + ": the file is empty");
  const std::string ext = extension(path);
  SceneModel model;
  model.format = format_of(ext);
  if (ext == ".glb" || ext == ".gltf") check_gltf(path, ext == ".glb");
  if (ext == ".3mf") check_3mf(path);
  if (ext == ".dae") check_collada(path);
  if (ext == ".fbx") check_fbx(path);
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_PreTransformVertices | aiProcess_SortByPType |
                                                     aiProcess_ValidateDataStructure);
  if (!scene) throw InvalidInput(path + ": Assimp: " + assimp_reason(importer.GetErrorString()));
  std::size_t meshes = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    ++meshes;
    const std::uint32_t base = std::uint32_t(model.mesh.positions.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw InvalidInput(path + ": mesh " + std::to_string(m) + " vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
      model.mesh.positions.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      const Triangle t{base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      model.mesh.triangles.push_back(t);
    }
  }
  if (model.mesh.triangles.empty()) throw InvalidInput(path + ": no triangles in the scene (" + std::to_string(scene->mNumMeshes) + " meshes)");
  model.mesh.compute_vertex_normals();

  std::string source = "file";
  if (ext == ".gltf" || ext == ".glb") {
    model.unit = "m";
    source = "file (glTF is in metres by its specification)";
  } else if (ext == ".dae") {
    model.unit = "m";
    source = "file (Collada <unit meter>, applied by Assimp: metres)";
  } else if (ext == ".fbx") {
    double cm_per_unit = 1.0;
    bool found = false;
    if (scene->mMetaData) {
      found = scene->mMetaData->Get("UnitScaleFactor", cm_per_unit);
      if (!found) {
        float f = 1.f;
        found = scene->mMetaData->Get("UnitScaleFactor", f);
        cm_per_unit = f;
      }
    }
    if (!(cm_per_unit > 0) || !std::isfinite(cm_per_unit)) cm_per_unit = 1.0;
    const double mm = 10.0 * cm_per_unit;
    model.unit = std::abs(mm - 1) < 1e-9 ? "mm" : std::abs(mm - 10) < 1e-9 ? "cm" : std::abs(mm - 1000) < 1e-6 ? "m" : std::abs(mm - 25.4) < 1e-6 ? "in" : "";
    if (model.unit.empty()) {
      // An unusual factor: keep it exactly by scaling here and calling the result millimetres.
      for (Vec3& p : model.mesh.positions) p *= float(mm);
      model.unit = "mm";
    }
    source = found ? "file (FBX UnitScaleFactor " + std::to_string(cm_per_unit) + " cm per unit)" : "default (FBX without UnitScaleFactor: centimetres)";
  } else if (ext == ".3mf") {
    model.unit = three_mf_unit(path, source);
  }
  model.facts["meshes"] = meshes;
  model.facts["file_unit"] = model.unit;
  model.facts["file_unit_read_from"] = source;
  model.facts["triangles"] = model.mesh.triangle_count();
  return model;
}

void write_scene(const TriangleMesh& mesh, const std::string& path) {
  const std::string ext = extension(path);
  std::string id;
  double scale = 1.0;  // mm to the format's unit as read_scene reads it
  if (ext == ".gltf") id = "gltf2", scale = 0.001;
  else if (ext == ".glb") id = "glb2", scale = 0.001;
  else if (ext == ".dae") id = "collada", scale = 0.001;
  else if (ext == ".3mf") id = "3mf", scale = 1.0;
  else if (ext == ".fbx") id = "fbxa", scale = 0.1;  // ASCII: Assimp 5.2 cannot read its own binary FBX
  else throw InvalidInput(path + ": write_scene writes .gltf .glb .3mf .dae .fbx");

  auto scene = std::make_unique<aiScene>();
  scene->mRootNode = new aiNode();
  scene->mMaterials = new aiMaterial*[1]{new aiMaterial()};
  scene->mNumMaterials = 1;
  scene->mMeshes = new aiMesh*[1]{new aiMesh()};
  scene->mNumMeshes = 1;
  // The mesh hangs from a child of the root: Assimp's 3MF exporter writes the root's children.
  auto* node = new aiNode("mesh");
  node->mParent = scene->mRootNode;
  node->mMeshes = new unsigned[1]{0};
  node->mNumMeshes = 1;
  scene->mRootNode->mChildren = new aiNode*[1]{node};
  scene->mRootNode->mNumChildren = 1;
  aiMesh* m = scene->mMeshes[0];
  m->mMaterialIndex = 0;
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mNumVertices = unsigned(mesh.vertex_count());
  m->mVertices = new aiVector3D[mesh.vertex_count()];
  m->mNormals = new aiVector3D[mesh.vertex_count()];
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const Vec3 p = mesh.positions[v] * float(scale);
    m->mVertices[v] = aiVector3D(p.x(), p.y(), p.z());
    const Vec3 n = v < mesh.normals.size() ? mesh.normals[v] : Vec3::UnitZ();
    m->mNormals[v] = aiVector3D(n.x(), n.y(), n.z());
  }
  m->mNumFaces = unsigned(mesh.triangle_count());
  m->mFaces = new aiFace[mesh.triangle_count()];
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    m->mFaces[t].mNumIndices = 3;
    m->mFaces[t].mIndices = new unsigned[3]{mesh.triangles[t][0], mesh.triangles[t][1], mesh.triangles[t][2]};
  }
  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), id, path) != AI_SUCCESS)
    throw IoError(path + ": Assimp could not write it: " + std::string(exporter.GetErrorString()));
}

} // namespace hb::vtk
