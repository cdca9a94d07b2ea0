#pragma once
// One function that opens every model HapticBox takes (meshes, medical volumes, CAD solids,
// everyday interchange formats) as the core's triangle mesh in millimetres. The CLI, the
// window and vtkHapticBoxMeshReader all go through it, so they see the same triangles.
#include "contact/workspace.h"
#include "mesh/mesh_io.h"
#include "mesh/triangle_mesh.h"
#include "volume_reader.h"
#include "isolated_reader.h"
#include <nlohmann/json.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace hb::vtk {

/// How a CAD solid (STEP, IGES) is tessellated.
struct CadOptions {
  /// Chordal deviation in mm (largest distance from a triangle to the exact surface). 0: derived
  /// from the force budget at the scale the solid is felt at (hb::make_workspace of its
  /// bounding-box diagonal under `workspace`): d = force_tolerance_n / k at the device, in
  /// model millimetres, clamped to [1e-4, 1e-2] x the solid's bounding-box diagonal: a
  /// deviation d moves the surface by at most d, so the spring force by at most k d, and a
  /// finer mesh would only cost triangles the force cannot feel.
  double chordal_deviation_mm = 0.0;
  double force_tolerance_n = 0.01;   ///< force error the tessellation may cause, N (> 0).
  hb::WorkspaceOptions workspace;    ///< the scale and stiffness the model is felt with.
  double angular_deviation_deg = 20.0;  ///< largest angle between neighbouring facets' normals.
  /// A file some of whose faces fail to translate or tessellate is refused (naming how many)
  /// unless this is set; then it loads with a warning.
  bool accept_lost_faces = false;
};

/// How a file becomes a model.
struct ModelOptions {
  /// The length of one unit of the file: "mm", "cm", "m", "um", "in" (or "inch"), "ft". Empty:
  /// the file's own unit where the format has one (NIfTI, DICOM, STEP, IGES, glTF, 3MF,
  /// Collada, FBX), else millimetres. The model is scaled to millimetres either way, which the
  /// force law's default (0.001 m per unit) then turns into metres.
  std::string unit;
  VolumeSurfaceOptions volume;
  CadOptions cad;
  /// Meshes: read .stl/.obj/.ply with VTK's readers rather than the core's.
  bool use_vtk_readers = false;
  /// Third-party readers (volumes, CAD, scenes, .vtp/.vtk, VTK's mesh readers) run in a child
  /// process killed after this many seconds (0: HB_READER_TIMEOUT_S, else 120 s) ...
  double reader_timeout_s = 0.0;
  /// ... and allowed this many megabytes of address space (0: HB_READER_MEMORY_MB, else
  /// 8192). HB_READER_ISOLATION=0 runs them in this process (debugging only).
  std::size_t reader_memory_mb = 0;
};

enum class ModelKind { Mesh, Volume, Cad, Scene };

/// A model as loaded, with where it came from.
struct LoadedModel {
  TriangleMesh mesh;             ///< in millimetres.
  MeshReadReport report;         ///< the mesh reader's report (meshes); warnings for all kinds.
  ModelKind kind = ModelKind::Mesh;
  std::string format;            ///< "OFF", "NIfTI", "DICOM series", "STEP", "glTF", ...
  std::string unit = "mm";       ///< the file's unit.
  std::string unit_source;       ///< "--unit", "file", or "default (the format has no unit)".
  double mm_per_unit = 1.0;      ///< the scale applied to the file's coordinates.
  /// CAD: the solid face each triangle comes from (a natural decomposition; empty otherwise).
  std::vector<std::uint32_t> face_ids;
  /// What `info` prints: volume dimensions, spacing, value range, labels, iso-value used;
  /// CAD solids, faces, bounding box, chordal deviation; scene meshes; units.
  nlohmann::json facts;
};

/// Millimetres per unit for a unit name (see ModelOptions::unit). Throws hb::InvalidInput for
/// an unknown name.
double mm_per_unit(const std::string& unit);

/// True when load_model would take the file as a volume, a CAD solid or an Assimp scene
/// rather than a plain mesh (by extension; a directory is a DICOM series).
bool is_volume_or_cad(const std::string& path);

/// The extensions load_model reads (for help texts and file dialogs), e.g. "*.off *.obj ...".
std::string model_file_patterns();

/// The name of the reader load_model uses for `path` in messages ("NRRD", "STEP", "glTF"...).
std::string reader_name(const std::string& path);

/// The limits a third-party reader runs under: the environment's (ReaderLimits::
/// from_environment), then the options' non-zero values.
ReaderLimits reader_limits(const ModelOptions& options);

/// Reads any model. Meshes (.off .obj .ply .stl .om) go through hb::read_mesh, .vtp/.vtk
/// through VTK's readers, volumes through read_volume + volume_surface, STEP/IGES through
/// OpenCASCADE, glTF/GLB/3MF/FBX/Collada through Assimp. Throws hb::IoError / hb::InvalidInput
/// naming the file and the cause (missing, garbage, no solid, no voxel at the iso-value, absurd
/// size: coordinates beyond 100 m once in millimetres). Every third-party reader runs in a
/// child process under reader_limits(options) (see isolated_reader.h): a crash, a hang or a
/// runaway allocation in it is an hb::InvalidInput naming the file and what happened.
LoadedModel load_model(const std::string& path, const ModelOptions& options = {});

} // namespace hb::vtk
