// load_model:
//  1. the kind follows the extension (a directory is a DICOM series);
//  2. each kind has its reader (core mesh readers, VTK polydata readers, read_volume and
//     volume_surface, OpenCASCADE, Assimp), which returns a core mesh in the file's unit and
//     what it knows of that unit;
//  3. the unit is settled (--unit, else the file's, else mm), the mesh scaled to millimetres
//     and checked for an absurd size, and the facts `info` prints are gathered.
#include "model_loader.h"
#include "string_util.h"
#include "errors.h"
#include "vtkHapticBoxUtilities.h"
#include "isolated_reader.h"
#include "polydata_files.h"
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkSTLReader.h>
#include <vtkXMLPolyDataReader.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#ifdef HB_HAVE_OCCT
#include "cad_reader.h"
#endif
#ifdef HB_HAVE_ASSIMP
#include "scene_reader.h"
#endif

namespace hb::vtk {

namespace {

namespace fs = std::filesystem;

bool is_cad(const std::string& ext) { return ext == ".step" || ext == ".stp" || ext == ".iges" || ext == ".igs"; }
bool is_scene(const std::string& ext) {
  return ext == ".gltf" || ext == ".glb" || ext == ".3mf" || ext == ".fbx" || ext == ".dae";
}

// Runs a VTK polydata reader, turning its errors into an exception naming the file.
template <class Reader>
vtkSmartPointer<vtkPolyData> read_with_vtk(const std::string& path) {
  vtkNew<Reader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  if (reader->GetErrorCode() != 0)
    throw InvalidInput(path + ": VTK reader failed (error code " + std::to_string(reader->GetErrorCode()) + ")");
  vtkSmartPointer<vtkPolyData> out = reader->GetOutput();
  if (!out || out->GetNumberOfPoints() == 0) throw InvalidInput(path + ": no points read");
  return out;
}

std::string format_name(const std::string& ext) {
  if (ext == ".off") return "OFF";
  if (ext == ".obj") return "OBJ";
  if (ext == ".ply") return "PLY";
  if (ext == ".stl") return "STL";
  if (ext == ".om") return "OpenMesh";
  if (ext == ".vtp") return "VTK XML polydata";
  if (ext == ".vtk") return "VTK legacy polydata";
  return ext;
}

} // namespace

double mm_per_unit(const std::string& unit) {
  const std::string u = lower(unit);
  if (u == "mm" || u == "millimetre" || u == "millimeter") return 1.0;
  if (u == "cm" || u == "centimetre" || u == "centimeter") return 10.0;
  if (u == "m" || u == "metre" || u == "meter") return 1000.0;
  if (u == "um" || u == "micrometre" || u == "micron") return 0.001;
  if (u == "in" || u == "inch") return 25.4;
  if (u == "ft" || u == "foot") return 304.8;
  throw InvalidInput("unknown unit '" + unit + "' (use mm, cm, m, um, in or ft)");
}

bool is_volume_or_cad(const std::string& path) {
  const std::string ext = vtkHapticBoxUtilities::Extension(path);
  return is_volume_path(path) || is_cad(ext) || is_scene(ext);
}

std::string model_file_patterns() {
  std::string p = "*.off *.obj *.ply *.stl *.om *.vtp *.vtk *.nii *.nii.gz *.mha *.mhd *.nrrd *.nhdr *.dcm";
#ifdef HB_HAVE_OCCT
  p += " *.step *.stp *.iges *.igs";
#endif
#ifdef HB_HAVE_ASSIMP
  p += " *.gltf *.glb *.3mf *.fbx *.dae";
#endif
  return p;
}

namespace {

// The whole load (reader, unit, facts), in whichever process runs it.
LoadedModel load_here(const std::string& path, const ModelOptions& options) {
  const std::string ext = vtkHapticBoxUtilities::Extension(path);
  LoadedModel model;
  std::string file_unit;  // the unit the file declares, empty when it has none
  if (is_volume_path(path)) {
    Volume volume = read_volume(path, options.volume.max_voxels);
    model.kind = ModelKind::Volume;
    model.format = volume.format;
    model.facts = volume.facts;
    model.mesh = volume_surface(volume, options.volume, path, &model.facts);
    file_unit = "mm";  // read_volume already maps voxels to millimetres
  } else if (is_cad(ext)) {
#ifdef HB_HAVE_OCCT
    CadModel cad = read_cad(path, options.cad);
    model.kind = ModelKind::Cad;
    model.format = cad.format;
    model.mesh = std::move(cad.mesh);
    model.face_ids = std::move(cad.face_ids);
    model.facts = cad.facts;
    for (std::string& w : cad.warnings) model.report.warnings.push_back(std::move(w));
    file_unit = "mm";  // OpenCASCADE converts the file's length unit to millimetres
#else
    throw InvalidInput(path + ": this build has no OpenCASCADE (STEP/IGES reader)");
#endif
  } else if (is_scene(ext)) {
#ifdef HB_HAVE_ASSIMP
    SceneModel scene = read_scene(path);
    model.kind = ModelKind::Scene;
    model.format = scene.format;
    model.mesh = std::move(scene.mesh);
    model.facts = scene.facts;
    for (std::string& w : scene.warnings) model.report.warnings.push_back(std::move(w));
    file_unit = scene.unit;
#else
    throw InvalidInput(path + ": this build has no Assimp (glTF/3MF/FBX/Collada reader)");
#endif
  } else {
    model.kind = ModelKind::Mesh;
    model.format = format_name(ext);
    const bool vtk_format = ext == ".vtp" || ext == ".vtk";
    if (vtk_format || (options.use_vtk_readers && (ext == ".stl" || ext == ".obj" || ext == ".ply"))) {
      if (!std::ifstream(path).good()) throw IoError(path + ": cannot open the file");
      vtkSmartPointer<vtkPolyData> raw;
      if (ext == ".vtp") {
        check_vtp_appended_data(path);
        raw = read_with_vtk<vtkXMLPolyDataReader>(path);
      }
      else if (ext == ".vtk") raw = read_with_vtk<vtkPolyDataReader>(path);
      else if (ext == ".stl") raw = read_with_vtk<vtkSTLReader>(path);
      else if (ext == ".obj") raw = read_with_vtk<vtkOBJReader>(path);
      else raw = read_with_vtk<vtkPLYReader>(path);
      try {
        model.mesh = vtkHapticBoxUtilities::ToTriangleMesh(raw);
      } catch (const Error& e) {
        throw InvalidInput(path + ": " + e.what());
      }
    } else {
      model.mesh = read_mesh(path, &model.report);
    }
  }

  // The unit: --unit wins, then the file's, then millimetres.
  if (!options.unit.empty()) {
    model.unit = options.unit;
    model.unit_source = "--unit";
    if (model.kind == ModelKind::Volume)
      model.report.warnings.push_back(path + ": --unit " + options.unit + " overrides the volume's own spacing unit (mm)");
  } else if (!file_unit.empty()) {
    model.unit = file_unit;
    model.unit_source = "file";
  } else {
    model.unit = "mm";
    model.unit_source = "default (the format has no unit)";
  }
  model.mm_per_unit = mm_per_unit(model.unit);
  if (model.mm_per_unit != 1.0) {
    for (Vec3& p : model.mesh.positions) p *= float(model.mm_per_unit);
  }
  // Absurd sizes: float coordinates beyond 10 km in mm lose sub-millimetre precision, and a
  // model that small or that large is a wrong unit far more often than a real object.
  const Bounds b = model.mesh.bounds();
  const float extent = std::max(b.min.cwiseAbs().maxCoeff(), b.max.cwiseAbs().maxCoeff());
  if (!(extent <= 1e7f))
    throw InvalidInput(path + ": coordinates reach " + std::to_string(extent) +
                       " mm (beyond 10 km): wrong unit? (see --unit)");
  if (!(b.diagonal() > 0.f)) throw InvalidInput(path + ": the model has no extent (all vertices at one point)");

  model.facts["kind"] = model.kind == ModelKind::Volume ? "volume" : model.kind == ModelKind::Cad ? "cad" : model.kind == ModelKind::Scene ? "scene" : "mesh";
  model.facts["format"] = model.format;
  model.facts["unit"] = model.unit;
  model.facts["unit_source"] = model.unit_source;
  model.facts["mm_per_unit"] = model.mm_per_unit;
  model.facts["model_bounds_mm"] = {{b.min.x(), b.min.y(), b.min.z()}, {b.max.x(), b.max.y(), b.max.z()}};
  return model;
}

// A model through the child process's shared memory: sized by a counting pass, then written
// in place (the facts as JSON text, dumped once).
void serialise(const LoadedModel& m, const std::string& facts, ByteWriter& w) {
  w.put_vector(m.mesh.positions);
  w.put_vector(m.mesh.triangles);
  w.put_vector(m.mesh.normals);
  const MeshReadReport& r = m.report;
  for (std::size_t n : {r.input_vertices, r.input_faces, r.polygons_triangulated, r.degenerate_dropped, r.faces_rejected})
    w.put<std::uint64_t>(n);
  w.put<char>(char(r.open));
  w.put<char>(char(r.non_manifold));
  w.put<char>(char(r.inconsistent_orientation));
  w.put<std::uint64_t>(r.warnings.size());
  for (const std::string& s : r.warnings) w.put_string(s);
  w.put<int>(int(m.kind));
  w.put_string(m.format);
  w.put_string(m.unit);
  w.put_string(m.unit_source);
  w.put<double>(m.mm_per_unit);
  w.put_vector(m.face_ids);
  w.put_string(facts);
}

void serialise(const LoadedModel& m, ResultSink& sink) {
  const std::string facts = m.facts.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);  // a file's bytes may not be UTF-8
  ByteWriter count = ByteWriter::counter();
  serialise(m, facts, count);
  ByteWriter w(sink.allocate(count.size()));
  serialise(m, facts, w);
}

LoadedModel deserialise(std::string_view bytes) {
  ByteReader r(bytes);
  LoadedModel m;
  r.get_vector(m.mesh.positions);
  r.get_vector(m.mesh.triangles);
  r.get_vector(m.mesh.normals);
  MeshReadReport& rep = m.report;
  for (std::size_t* n : {&rep.input_vertices, &rep.input_faces, &rep.polygons_triangulated, &rep.degenerate_dropped, &rep.faces_rejected})
    *n = std::size_t(r.get<std::uint64_t>());
  rep.open = r.get<char>() != 0;
  rep.non_manifold = r.get<char>() != 0;
  rep.inconsistent_orientation = r.get<char>() != 0;
  const std::uint64_t warnings = r.get<std::uint64_t>();
  for (std::uint64_t i = 0; i < warnings; ++i) rep.warnings.push_back(r.get_string());
  m.kind = ModelKind(r.get<int>());
  m.format = r.get_string();
  m.unit = r.get_string();
  m.unit_source = r.get_string();
  m.mm_per_unit = r.get<double>();
  r.get_vector(m.face_ids);
  m.facts = nlohmann::json::parse(r.get_string());
  return m;
}

} // namespace

std::string reader_name(const std::string& path) {
  if (fs::is_directory(path)) return "DICOM";
  const std::string p = lower(path);
  if (ends_with(p, ".nii") || ends_with(p, ".nii.gz") || ends_with(p, ".hdr") || ends_with(p, ".hdr.gz")) return "NIfTI";
  if (ends_with(p, ".mha") || ends_with(p, ".mhd")) return "MetaImage";
  if (ends_with(p, ".nrrd") || ends_with(p, ".nhdr")) return "NRRD";
  if (ends_with(p, ".dcm")) return "DICOM";
  const std::string ext = vtkHapticBoxUtilities::Extension(path);
  if (ext == ".step" || ext == ".stp") return "STEP";
  if (ext == ".iges" || ext == ".igs") return "IGES";
  if (ext == ".gltf" || ext == ".glb") return "glTF";
  if (ext == ".3mf") return "3MF";
  if (ext == ".fbx") return "FBX";
  if (ext == ".dae") return "Collada";
  if (ext == ".vtp") return "VTK XML polydata";
  if (ext == ".vtk") return "VTK legacy";
  return "VTK " + format_name(ext);
}

ReaderLimits reader_limits(const ModelOptions& options) {
  ReaderLimits limits = ReaderLimits::from_environment();
  if (options.reader_timeout_s > 0) limits.timeout_s = options.reader_timeout_s;
  if (options.reader_memory_mb > 0) limits.memory_mb = options.reader_memory_mb;
  return limits;
}

LoadedModel load_model(const std::string& path, const ModelOptions& options) {
  if (!fs::exists(path)) throw IoError(path + ": no such file");
  const std::string ext = vtkHapticBoxUtilities::Extension(path);
  // The core's own readers (hostile-input tested, and the 50M-triangle meshes) run here; every
  // third-party reader runs in a child process.
  const bool foreign = is_volume_or_cad(path) || ext == ".vtp" || ext == ".vtk" ||
                       (options.use_vtk_readers && (ext == ".stl" || ext == ".obj" || ext == ".ply"));
  if (!foreign) return load_here(path, options);
  LoadedModel model;
  run_isolated_shared(
      path, reader_name(path), reader_limits(options), [&](ResultSink& sink) { serialise(load_here(path, options), sink); },
      [&](std::string_view bytes) { model = deserialise(bytes); });
  return model;
}

} // namespace hb::vtk
