#pragma once
// The files HapticBox writes for ParaView and MeshLab users: VTK XML PolyData (.vtp) written
// whole or not at all, with units and provenance as field data. ParaView reads every array of
// these files as is: cell data "PieceId" colours pieces, point data carries N, N/m, degrees
// (units in the field data array "Units", and on each array's vtkDataArray::UNITS_LABEL),
// NaN marks "no data" (ParaView's "NaN colour"), never a measured zero.
#include "mesh/triangle_mesh.h"
#include <vtkSmartPointer.h>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

class vtkDataArray;
class vtkFieldData;
class vtkPolyData;

namespace hb {
class BoxScene;
}

namespace hb::vtk {

/// Writes `data` as VTK XML PolyData (appended raw binary) to `path`: written under
/// `path + ".tmp"` and renamed, so the file appears whole or not at all. Throws hb::IoError
/// naming the file.
void write_polydata_xml(vtkPolyData* data, const std::string& path);

/// The mesh as triangles (cell i = triangle i) with a cell array "PieceId" (int, one id per
/// triangle) and point "Normals". Throws hb::InvalidInput when the sizes differ.
vtkSmartPointer<vtkPolyData> piece_polydata(const TriangleMesh& mesh, const std::vector<std::uint32_t>& piece_of_triangle);

/// The "PieceId" cell array of a .vtp file (as written by piece_polydata, or any polydata with
/// an integer cell array of that name), one id per polygon, checked against `triangle_count`
/// (0: not checked here; hb::bake checks the count against the mesh).
/// Throws hb::IoError (unreadable) or hb::InvalidInput (no PieceId, wrong count, negative id).
std::vector<std::uint32_t> read_piece_vtp(const std::string& path, std::size_t triangle_count);

/// A VTK XML PolyData file held to its header before VTK's reader allocates anything
/// (vtp_file_check.cxx): each section and array once, every appended array's offset and byte
/// count (or compressed blocks) within the file and within deflate's reach, inline ascii arrays
/// of numbers only, the point and cell arrays as long as the piece's NumberOfPoints and cell
/// counts make them, and the cells: one offset a cell, never decreasing, ending at the
/// connectivity's length, connectivity naming points of the piece. Base64 data is left to VTK
/// (in its child process). Throws hb::InvalidInput naming the file and the array.
void check_vtp_appended_data(const std::string& path);

/// The scene's box outlines (12 lines a box) with cell arrays "PieceId" (box index), "M", "N".
vtkSmartPointer<vtkPolyData> box_outline_polydata(const BoxScene& scene);

/// One string-valued and one number-valued entry of a file's provenance.
struct Provenance {
  std::vector<std::pair<std::string, std::string>> strings;  ///< e.g. {"HapticBoxVersion", "0.1.0"}
  std::vector<std::pair<std::string, double>> numbers;       ///< e.g. {"Stiffness_N_per_m", 500}
};

/// Adds each entry as a one-tuple field data array named after it (vtkStringArray or
/// vtkDoubleArray), replacing arrays of the same name.
void add_provenance(vtkFieldData* field_data, const Provenance& provenance);

/// Sets `array`'s vtkDataArray::UNITS_LABEL and appends "Name: unit" to the field data string
/// array "Units" (created when missing).
void label_units(vtkFieldData* field_data, vtkDataArray* array, const std::string& unit);

/// One sample of a recorded trajectory, in model units.
struct TrajectorySample {
  double time_s = 0.0;
  Vec3 tip{Vec3::Zero()};         ///< probe tip, model units.
  Vec3 force{Vec3::Zero()};       ///< force sent to the device, N.
  float depth = 0.f;              ///< contact depth, model units.
  bool contact = false;
  std::uint32_t query_ns = 0;
  std::uint32_t safety_flags = 0;
};

/// A polyline through the samples (one line cell; vertices in time order) with point arrays
/// "Time" (s), "Force" (N, 3 components), "ForceMagnitude" (N), "Depth" (model units),
/// "Contact" (0/1), "QueryTime" (ns), "SafetyFlags".
vtkSmartPointer<vtkPolyData> trajectory_polydata(const std::vector<TrajectorySample>& samples);

} // namespace hb::vtk
