// Volumes in patient millimetres:
//  1. read_volume picks the reader by extension (a directory is a DICOM series, dicom_series.h),
//     holds the data to the header before any voxel is read (volume_data_check.h), and builds
//     index_to_mm from the format's own geometry: NIfTI sform (else qform) times VTK's
//     spacing, MetaImage TransformMatrix and Offset, NRRD space directions and space origin
//     (those two headers are parsed here since VTK 9.1's readers drop the direction).
//  2. The image is then put in index space (origin 0, spacing 1) so one contouring path serves
//     every format (volume_surface.cxx): points in voxel indices, mapped to millimetres by
//     index_to_mm.
//  3. The facts `info` prints: dimensions, spacing, direction, value range, labels.
#include "volume_reader.h"
#include "dicom_series.h"
#include "string_util.h"
#include "errors.h"
#include "volume_data_check.h"
#include "vtk_error_catcher.h"
#include "formats/dicom_header.h"
#include "formats/volume_headers.h"
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkMatrix3x3.h>
#include <vtkMatrix4x4.h>
#include <vtkMetaImageReader.h>
#include <vtkNIFTIImageHeader.h>
#include <vtkNIFTIImageReader.h>
#include <vtkNrrdReader.h>
#include <vtkPointData.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace hb::vtk {

namespace {

namespace fs = std::filesystem;

// Runs a reader in two steps (header, then data) so an absurd size is refused before any
// allocation.
template <class Reader>
void run_reader(Reader* reader, const std::string& path, std::size_t max_voxels) {
  ErrorCatcher errors(reader);
  ErrorCatcher pipeline(reader->GetExecutive());  // "returned failure" repeats the reader's error: kept off the console
  reader->UpdateInformation();
  if (errors.failed()) throw InvalidInput(path + ": " + errors.message());
  check_size(path, reader->GetDataExtent(), max_voxels);
  reader->Update();
  if (errors.failed()) throw InvalidInput(path + ": " + errors.message());
  if (!reader->GetOutput() || !reader->GetOutput()->GetPointData()->GetScalars())
    throw InvalidInput(path + ": no voxel data read");
}

// index_to_mm from a VTK image's origin and spacing, pre-multiplied by `world` (4x4).
Eigen::Matrix4d image_matrix(vtkImageData* image, const Eigen::Matrix4d& world) {
  double s[3], o[3];
  image->GetSpacing(s);
  image->GetOrigin(o);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int a = 0; a < 3; ++a) {
    m(a, a) = s[a];
    m(a, 3) = o[a];
  }
  return world * m;
}

Eigen::Matrix4d to_eigen(vtkMatrix4x4* m) {
  Eigen::Matrix4d e;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) e(r, c) = m->GetElement(r, c);
  return e;
}

// The image in index space: origin 0, spacing 1, direction identity (data shared).
vtkSmartPointer<vtkImageData> index_space(vtkImageData* image) {
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(image);
  out->SetOrigin(0, 0, 0);
  out->SetSpacing(1, 1, 1);
  out->SetDirectionMatrix(1, 0, 0, 0, 1, 0, 0, 0, 1);
  return out;
}

// "key = value" (MetaImage) or "key: value" (NRRD) lines of a text header, up to the data.
std::map<std::string, std::string> read_header(const std::string& path, char separator, const std::string& stop_key) {
  std::ifstream in(path, std::ios::binary);
  std::map<std::string, std::string> keys;
  std::string line;
  for (int lines = 0; lines < 200 && std::getline(in, line); ++lines) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (separator == ':' && line.empty()) break;  // NRRD: a blank line ends the header
    const std::size_t at = line.find(separator);
    if (at == std::string::npos) continue;
    std::string key = line.substr(0, at), value = line.substr(at + 1);
    auto trim = [](std::string& s) {
      s.erase(0, s.find_first_not_of(" \t"));
      s.erase(s.find_last_not_of(" \t") + 1);
    };
    trim(key);
    if (!value.empty() && value[0] == '=') value.erase(0, 1);  // NRRD "key:=value" comments
    trim(value);
    keys[lower(key)] = value;
    if (lower(key) == stop_key) break;
  }
  return keys;
}

std::vector<double> numbers(std::string text) {
  for (char& c : text)
    if (c == '(' || c == ')' || c == ',') c = ' ';
  std::istringstream in(text);
  std::vector<double> v;
  for (std::string w; in >> w;) {
    char* end = nullptr;
    const double d = std::strtod(w.c_str(), &end);
    if (end == w.c_str()) return {};  // "none" or a word
    v.push_back(d);
  }
  return v;
}

void check_matrix(const std::string& path, const Eigen::Matrix4d& m) {
  if (!m.allFinite()) throw InvalidInput(path + ": the voxel-to-world matrix has a NaN or infinite entry");
  for (int a = 0; a < 3; ++a) {
    const double len = m.block<3, 1>(0, a).norm();
    if (!(len > 1e-6) || len > 1e4)
      throw InvalidInput(path + ": voxel spacing along axis " + std::to_string(a) + " is " + std::to_string(len) +
                         " mm (must be > 0 and at most 10 m)");
  }
  if (std::abs(m.block<3, 3>(0, 0).determinant()) < 1e-12)
    throw InvalidInput(path + ": the voxel axes are degenerate (direction matrix has no inverse)");
}

Volume read_nifti(const std::string& path, std::size_t max_voxels) {
  check_nifti_file(path, max_voxels);
  vtkNew<vtkNIFTIImageReader> reader;
  reader->SetFileName(path.c_str());
  run_reader(reader.Get(), path, max_voxels);
  Volume v;
  v.format = "NIfTI";
  // Prefer sform (scanner or template space), else qform; both as VTK corrected them for qfac.
  vtkMatrix4x4* world = reader->GetSFormMatrix() ? reader->GetSFormMatrix() : reader->GetQFormMatrix();
  v.index_to_mm = image_matrix(reader->GetOutput(), world ? to_eigen(world) : Eigen::Matrix4d::Identity());
  double to_mm = 1.0;
  std::string unit = "mm";
  switch (reader->GetNIFTIHeader()->GetXYZTUnits() & 7) {
    case 1: to_mm = 1000.0; unit = "m"; break;
    case 3: to_mm = 0.001; unit = "um"; break;
    case 2: break;
    default: unit = "unknown (mm assumed)"; break;
  }
  v.index_to_mm.block<3, 4>(0, 0) *= to_mm;
  v.slope = reader->GetRescaleSlope() != 0.0 ? reader->GetRescaleSlope() : 1.0;
  v.intercept = reader->GetRescaleSlope() != 0.0 ? reader->GetRescaleIntercept() : 0.0;
  v.facts["orientation_from"] = reader->GetSFormMatrix() ? "sform" : reader->GetQFormMatrix() ? "qform" : "none (identity)";
  v.facts["file_unit"] = unit;
  if (reader->GetTimeDimension() > 1) v.facts["time_points"] = reader->GetTimeDimension();
  v.image = index_space(reader->GetOutput());
  return v;
}

Volume read_metaimage(const std::string& path, std::size_t max_voxels) {
  vtkNew<vtkMetaImageReader> reader;
  reader->SetFileName(path.c_str());
  if (!reader->CanReadFile(path.c_str())) throw InvalidInput(path + ": not a MetaImage file (no ObjectType/NDims header)");
  check_volume_data(path, check_metaimage_header(path, file_head(path, 1 << 16, false)), max_voxels);
  run_reader(reader.Get(), path, max_voxels);
  Volume v;
  v.format = "MetaImage";
  const auto keys = read_header(path, '=', "elementdatafile");
  Eigen::Matrix4d world = Eigen::Matrix4d::Identity();
  for (const char* key : {"transformmatrix", "rotation", "orientation"}) {
    auto it = keys.find(key);
    if (it == keys.end()) continue;
    const std::vector<double> d = numbers(it->second);
    if (d.size() != 9) throw InvalidInput(path + ": " + std::string(key) + " must hold 9 numbers, not '" + it->second + "'");
    // MetaIO (as ITK writes it) stores the direction of axis a as numbers 3a..3a+2.
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) world(r, a) = d[std::size_t(3 * a + r)];
    break;
  }
  // VTK applies spacing and offset in its own axes; the offset is the world position of voxel 0.
  double s[3], o[3];
  reader->GetOutput()->GetSpacing(s);
  reader->GetOutput()->GetOrigin(o);
  v.index_to_mm = Eigen::Matrix4d::Identity();
  for (int a = 0; a < 3; ++a) {
    v.index_to_mm.block<3, 1>(0, a) = world.block<3, 1>(0, a) * s[a];
    v.index_to_mm(a, 3) = o[a];
  }
  v.slope = reader->GetRescaleSlope() != 0.0 ? reader->GetRescaleSlope() : 1.0;
  v.intercept = reader->GetRescaleSlope() != 0.0 ? reader->GetRescaleOffset() : 0.0;
  if (reader->GetAnatomicalOrientation() && *reader->GetAnatomicalOrientation())
    v.facts["anatomical_orientation"] = reader->GetAnatomicalOrientation();
  v.image = index_space(reader->GetOutput());
  return v;
}

Volume read_nrrd(const std::string& path, std::size_t max_voxels) {
  vtkNew<vtkNrrdReader> reader;
  reader->SetFileName(path.c_str());
  if (!reader->CanReadFile(path.c_str())) throw InvalidInput(path + ": not a NRRD file (no NRRD magic)");
  check_volume_data(path, check_nrrd_header(path, file_head(path, 1 << 16, false)), max_voxels);
  run_reader(reader.Get(), path, max_voxels);
  Volume v;
  v.format = "NRRD";
  const auto keys = read_header(path, ':', "");
  v.index_to_mm = image_matrix(reader->GetOutput(), Eigen::Matrix4d::Identity());
  if (auto it = keys.find("space directions"); it != keys.end()) {
    const std::vector<double> d = numbers(it->second);
    if (d.size() != 9) throw InvalidInput(path + ": 'space directions' must hold three 3-vectors, not '" + it->second + "'");
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) v.index_to_mm(r, a) = d[std::size_t(3 * a + r)];
    if (auto o = keys.find("space origin"); o != keys.end()) {
      const std::vector<double> p = numbers(o->second);
      if (p.size() != 3) throw InvalidInput(path + ": 'space origin' must be a 3-vector, not '" + o->second + "'");
      for (int r = 0; r < 3; ++r) v.index_to_mm(r, 3) = p[std::size_t(r)];
    }
  }
  if (auto it = keys.find("space"); it != keys.end()) v.facts["space"] = it->second;
  v.image = index_space(reader->GetOutput());
  return v;
}

} // namespace

bool is_volume_path(const std::string& path) {
  if (fs::is_directory(path)) return true;
  const std::string p = lower(path);
  for (const char* ext : {".nii", ".nii.gz", ".hdr", ".hdr.gz", ".mha", ".mhd", ".nrrd", ".nhdr", ".dcm"})
    if (ends_with(p, ext)) return true;
  // A DICOM file without an extension (as scanners write them): "DICM" at byte 128.
  std::error_code ec;
  if (fs::path(path).extension().empty() && fs::is_regular_file(path, ec)) return looks_like_dicom(file_head(path, 132, false));
  return false;
}

Volume read_volume(const std::string& path, std::size_t max_voxels) {
  if (!fs::exists(path)) throw IoError(path + ": no such file or directory");
  if (!fs::is_directory(path) && !std::ifstream(path).good()) throw IoError(path + ": cannot open the file");
  if (!fs::is_directory(path) && fs::file_size(path) == 0) throw IoError(path + ": the file is empty");
  const std::string p = lower(path);
  Volume v;
  if (fs::is_directory(path) || ends_with(p, ".dcm") || (fs::path(path).extension().empty() && looks_like_dicom(file_head(path, 132, false))))
    v = read_dicom_series(path, max_voxels);
  else if (ends_with(p, ".nii") || ends_with(p, ".nii.gz") || ends_with(p, ".hdr") || ends_with(p, ".hdr.gz"))
    v = read_nifti(path, max_voxels);
  else if (ends_with(p, ".mha") || ends_with(p, ".mhd")) v = read_metaimage(path, max_voxels);
  else if (ends_with(p, ".nrrd") || ends_with(p, ".nhdr")) v = read_nrrd(path, max_voxels);
  else throw InvalidInput(path + ": not a volume format (.nii .nii.gz .mha .mhd .nrrd .nhdr, or a DICOM directory)");
  check_matrix(path, v.index_to_mm);

  int dims[3];
  v.image->GetDimensions(dims);
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
    throw InvalidInput(path + ": " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " + std::to_string(dims[2]) +
                       " voxels is not a volume (an isosurface needs at least 2 voxels along each axis)");
  vtkDataArray* scalars = v.image->GetPointData()->GetScalars();
  double range[2];
  scalars->GetRange(range, 0);
  if (!std::isfinite(range[0]) || !std::isfinite(range[1])) throw InvalidInput(path + ": the voxels hold NaN or infinite values");
  double lo = range[0] * v.slope + v.intercept, hi = range[1] * v.slope + v.intercept;
  if (lo > hi) std::swap(lo, hi);
  nlohmann::json& f = v.facts;
  f["format"] = v.format;
  f["dimensions"] = {dims[0], dims[1], dims[2]};
  f["voxels"] = double(dims[0]) * dims[1] * dims[2];
  std::vector<double> spacing, origin;
  nlohmann::json direction = nlohmann::json::array();
  for (int a = 0; a < 3; ++a) {
    spacing.push_back(v.index_to_mm.block<3, 1>(0, a).norm());
    origin.push_back(v.index_to_mm(a, 3));
  }
  for (int r = 0; r < 3; ++r) {
    std::vector<double> row;
    for (int a = 0; a < 3; ++a) row.push_back(std::round(v.index_to_mm(r, a) / spacing[std::size_t(a)] * 1e6) / 1e6);
    direction.push_back(row);
  }
  f["spacing_mm"] = spacing;
  f["origin_mm"] = origin;
  f["direction"] = direction;
  f["size_mm"] = {spacing[0] * (dims[0] - 1), spacing[1] * (dims[1] - 1), spacing[2] * (dims[2] - 1)};
  f["scalar_type"] = v.image->GetScalarTypeAsString();
  f["value_range"] = {lo, hi};
  if (v.slope != 1.0 || v.intercept != 0.0) f["rescale"] = {{"slope", v.slope}, {"intercept", v.intercept}};
  // Integer volumes with few distinct values are probably label maps: list them.
  if (scalars->GetDataType() != VTK_FLOAT && scalars->GetDataType() != VTK_DOUBLE && range[1] - range[0] <= 4096) {
    std::vector<std::size_t> counts(std::size_t(range[1] - range[0]) + 1, 0);
    const vtkIdType n = scalars->GetNumberOfTuples();
    for (vtkIdType i = 0; i < n; ++i) ++counts[std::size_t(scalars->GetComponent(i, 0) - range[0])];
    std::size_t distinct = 0;
    for (std::size_t c : counts) distinct += c ? 1 : 0;
    if (distinct <= 64) {
      nlohmann::json labels = nlohmann::json::object();
      for (std::size_t i = 0; i < counts.size(); ++i)
        if (counts[i]) labels[std::to_string(long(range[0]) + long(i))] = counts[i];
      f["labels"] = labels;
    }
  }
  return v;
}

} // namespace hb::vtk
