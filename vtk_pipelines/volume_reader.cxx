// Volumes to surfaces in patient millimetres.
//  1. read_volume picks the reader by extension (a directory is a DICOM series), checks the
//     header's size before any voxel is read, and builds index_to_mm from the format's own
//     geometry: NIfTI sform (else qform) times VTK's spacing, DICOM ImagePositionPatient /
//     ImageOrientationPatient / PixelSpacing plus the measured slice step, MetaImage
//     TransformMatrix and Offset, NRRD space directions and space origin (those two headers
//     are parsed here since VTK 9.1's readers drop the direction).
//  2. The image is then put in index space (origin 0, spacing 1) so one contouring path serves
//     every format: flying edges at the stored iso-value (or discrete flying edges at a label)
//     produce points in voxel indices, which index_to_mm maps to millimetres.
//  3. Smoothing (windowed sinc) and decimation (quadric) run in millimetres, so anisotropic
//     voxels are smoothed evenly.
//  4. The winding is chosen by sampling the volume just off a few thousand triangles along
//     their normals: normals point to where the value is below the iso-value (or another
//     label), i.e. out of the bright region, whatever the handedness of index_to_mm.
#include "volume_reader.h"
#include "volume_histogram.h"
#include "string_util.h"
#include "errors.h"
#include "vtkHapticBoxUtilities.h"
#include "formats/dicom_header.h"
#include "formats/volume_headers.h"
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDICOMImageReader.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkMatrix3x3.h>
#include <vtkMatrix4x4.h>
#include <vtkMetaImageReader.h>
#include <vtkNIFTIImageHeader.h>
#include <vtkNIFTIImageReader.h>
#include <vtkNrrdReader.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadricDecimation.h>
#include <vtkWindowedSincPolyDataFilter.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <zlib.h>

namespace hb::vtk {

namespace {

namespace fs = std::filesystem;
using hb::VolumeLayout;
using hb::DicomHeader;

// Collects a VTK algorithm's error messages (and keeps them off the console) so that they can
// be rethrown with the file's name.
class ErrorCatcher {
public:
  explicit ErrorCatcher(vtkObject* watched) : watched_(watched) {
    callback_->SetClientData(this);
    callback_->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
      auto* self = static_cast<ErrorCatcher*>(client);
      if (call) self->messages_ += (self->messages_.empty() ? "" : "; ") + std::string(static_cast<const char*>(call));
    });
    tag_ = watched_->AddObserver(vtkCommand::ErrorEvent, callback_);
  }
  ~ErrorCatcher() { watched_->RemoveObserver(tag_); }
  ErrorCatcher(const ErrorCatcher&) = delete;
  ErrorCatcher& operator=(const ErrorCatcher&) = delete;
  // VTK's messages read "ERROR: In file, line N\nclass (ptr): text\n\n", one after another:
  // keep the text of each (never an empty cause: the raw message when nothing is left).
  std::string message() const {
    std::string out;
    std::size_t at = 0;
    while (at < messages_.size()) {
      std::size_t next = messages_.find("; ERROR: ", at);
      std::string m = messages_.substr(at, next == std::string::npos ? std::string::npos : next - at);
      at = next == std::string::npos ? messages_.size() : next + 2;
      if (m.rfind("ERROR: In ", 0) == 0) {
        const std::size_t nl = m.find('\n');
        if (nl != std::string::npos) m = m.substr(nl + 1);
      }
      const std::size_t colon = m.find("): ");
      if (colon != std::string::npos && colon < 80) m = m.substr(colon + 3);
      for (char& c : m)
        if (c == '\n' || c == '\r') c = ' ';
      while (!m.empty() && std::isspace((unsigned char)m.back())) m.pop_back();
      while (!m.empty() && std::isspace((unsigned char)m.front())) m.erase(0, 1);
      if (m.empty() || out.find(m) != std::string::npos) continue;
      out += (out.empty() ? "" : "; ") + m;
    }
    if (out.empty()) out = "the VTK reader reported an error without a reason";
    return out;
  }
  bool failed() const { return !messages_.empty(); }

private:
  vtkObject* watched_;
  vtkNew<vtkCallbackCommand> callback_;
  unsigned long tag_ = 0;
  std::string messages_;
};

void check_size(const std::string& path, const int* extent, std::size_t max_voxels) {
  std::size_t voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const long n = long(extent[2 * a + 1]) - long(extent[2 * a]) + 1;
    if (n <= 0) throw InvalidInput(path + ": the volume is empty (dimension " + std::to_string(a) + " is " + std::to_string(n) + ")");
    if (voxels > max_voxels / std::size_t(n) + 1) voxels = max_voxels + 1;
    else voxels *= std::size_t(n);
  }
  if (voxels > max_voxels)
    throw InvalidInput(path + ": the volume's header claims " + std::to_string(extent[1] - extent[0] + 1) + " x " +
                       std::to_string(extent[3] - extent[2] + 1) + " x " + std::to_string(extent[5] - extent[4] + 1) +
                       " voxels, more than the " + std::to_string(max_voxels) + " accepted");
}


// ---- The data held to the header, before VTK reads it -----------------------------------

// The first `n` bytes of a file (of its decompressed content when `gz`).
std::string file_head(const std::string& path, std::size_t n, bool gz) {
  std::string out(n, '\0');
  if (gz) {
    gzFile f = gzopen(path.c_str(), "rb");
    if (!f) throw IoError(path + ": cannot open the file");
    const int got = gzread(f, out.data(), unsigned(n));
    int err = 0;
    const std::string why = got < 0 ? gzerror(f, &err) : "";
    gzclose(f);
    if (got < 0) throw InvalidInput(path + ": the gzip stream is damaged (" + why + ")");
    out.resize(std::size_t(got));
    return out;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the file");
  in.read(out.data(), std::streamsize(n));
  out.resize(std::size_t(in.gcount()));
  return out;
}

std::string describe(const VolumeLayout& l) {
  std::ostringstream o;
  o << l.sizes[0] << " x " << l.sizes[1] << " x " << l.sizes[2];
  if (l.sizes[3] > 1) o << " x " << l.sizes[3];
  o << " voxels";
  if (l.components > 1) o << " of " << l.components << " values";
  o << " of " << l.bytes_per_element << " bytes";
  return o.str();
}

// Decoded bytes available in `file` from byte `offset` in `encoding`, counted up to `want`
// (stops there). Damaged compressed streams and non-numbers in text data are errors.
std::uint64_t decoded_bytes(const std::string& name, const std::string& file, std::uint64_t offset, const std::string& encoding,
                            std::uint64_t want, unsigned bytes_per_element) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw InvalidInput(name + ": the data file " + file + " is missing or not a regular file");
  const std::uint64_t size = fs::file_size(file, ec);
  if (ec) throw IoError(name + ": cannot read the data file " + file);
  if (encoding == "raw") return size > offset ? size - offset : 0;
  std::ifstream in(file, std::ios::binary);
  in.seekg(std::streamoff(std::min(offset, size)));
  if (encoding == "text") {
    std::uint64_t values = 0;
    for (std::string w; values * bytes_per_element < want && in >> w;) {
      char* end = nullptr;
      std::strtod(w.c_str(), &end);
      if (end == w.c_str() || *end)
        throw InvalidInput(name + ": the text-encoded data holds " + (w.size() > 20 ? w.substr(0, 20) + "..." : w) +
                           ", not a number (binary data with a text encoding?)");
      ++values;
    }
    return values * bytes_per_element;
  }
  // gzip (NRRD) or zlib (MetaImage): inflate, counting the output.
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw InvalidInput(name + ": zlib could not start");
  std::vector<unsigned char> input(1 << 16), output(1 << 18);
  std::uint64_t total = 0;
  int rc = Z_OK;
  while (total < want && rc != Z_STREAM_END) {
    if (z.avail_in == 0) {
      in.read(reinterpret_cast<char*>(input.data()), std::streamsize(input.size()));
      z.next_in = input.data();
      z.avail_in = unsigned(in.gcount());
      if (z.avail_in == 0) break;  // the stream is cut short
    }
    z.next_out = output.data();
    z.avail_out = unsigned(output.size());
    rc = inflate(&z, Z_NO_FLUSH);
    if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) {
      const std::string why = z.msg ? z.msg : "error " + std::to_string(rc);
      inflateEnd(&z);
      throw InvalidInput(name + ": the compressed voxel data in " + file + " is damaged (zlib: " + why + ")");
    }
    total += output.size() - z.avail_out;
  }
  inflateEnd(&z);
  return total;
}

// Holds the data (inline or in data files beside `name`) to what the header declares.
void check_volume_data(const std::string& name, const VolumeLayout& layout, std::size_t max_voxels) {
  if (layout.voxels() * layout.components > max_voxels)
    throw InvalidInput(name + ": the volume's header claims " + describe(layout) + ", more than the " + std::to_string(max_voxels) +
                       " voxels accepted");
  const std::uint64_t want = layout.expected_bytes() + (layout.data_at_end ? 0 : layout.skip);
  const fs::path dir = fs::path(name).parent_path();
  std::uint64_t have = 0;
  // One block of binary data must be exactly as long as the header makes it: extra bytes mean
  // wrong sizes or type in the header, or data shifted by an insertion (read as garbage).
  const bool exact = layout.encoding != "text" && !layout.data_at_end && layout.data_files.size() <= 1;
  if (layout.data_files.empty()) {
    have = decoded_bytes(name, name, layout.data_offset, layout.encoding, want + (exact ? 1 : 0), layout.bytes_per_element);
  } else if (exact) {
    const std::string& f = layout.data_files.front();
    const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : dir / f;
    have = decoded_bytes(name, p.string(), 0, layout.encoding, want + 1, layout.bytes_per_element);
  } else {
    for (const std::string& f : layout.data_files) {
      if (have >= want) break;
      const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : dir / f;
      have += decoded_bytes(name, p.string(), 0, layout.encoding, want - have, layout.bytes_per_element);
    }
  }
  if (have < want) {
    std::ostringstream msg;
    msg << name << ": the header declares " << describe(layout) << " (" << want << " bytes";
    if (layout.encoding != "raw") msg << " once decoded from " << layout.encoding;
    msg << ") but the data holds only " << have << " bytes: the volume is truncated or its header is wrong";
    throw InvalidInput(msg.str());
  }
  if (exact && have > want) {
    std::ostringstream msg;
    msg << name << ": the header declares " << describe(layout) << " (" << want << " bytes";
    if (layout.encoding != "raw") msg << " once decoded from " << layout.encoding;
    msg << ") but the data holds more: the header's sizes or type are wrong, or the data was altered";
    throw InvalidInput(msg.str());
  }
}

void check_nifti_file(const std::string& path, std::size_t max_voxels) {
  const std::string p = lower(path);
  const bool gz = ends_with(p, ".gz");
  const VolumeLayout layout = check_nifti_header(path, file_head(path, 540, gz));
  if (layout.voxels() > max_voxels)
    throw InvalidInput(path + ": the volume's header claims " + describe(layout) + ", more than the " + std::to_string(max_voxels) +
                       " voxels accepted");
  const std::uint64_t want = layout.data_offset + layout.expected_bytes();
  if (layout.data_files.empty()) {  // single file: the voxels follow the header
    const std::uint64_t have = decoded_bytes(path, path, 0, gz ? "gzip" : "raw", want + 1, 1);
    if (have < want)
      throw InvalidInput(path + ": the header declares " + describe(layout) + " from byte " + std::to_string(layout.data_offset) +
                         " (" + std::to_string(want) + " bytes) but the file holds " + std::to_string(have) +
                         (gz ? " once decompressed" : "") + ": the volume is truncated or its header is wrong");
    if (have > want)
      throw InvalidInput(path + ": the file holds more than the " + std::to_string(want) + " bytes its header declares (" + describe(layout) +
                         " from byte " + std::to_string(layout.data_offset) + "): the header's sizes or type are wrong, or the data was altered");
    return;
  }
  // A header and image pair: X.hdr with X.img (or their .gz).
  const std::string base = path.substr(0, path.size() - (gz ? 7 : 4));
  std::string img_path;
  for (const char* ext : {".img", ".img.gz", ".IMG", ".IMG.gz"})
    if (img_path.empty() && fs::exists(base + ext)) img_path = base + ext;
  if (img_path.empty()) throw InvalidInput(path + ": the NIfTI header's image file " + base + ".img is missing");
  const std::uint64_t have = decoded_bytes(path, img_path, 0, ends_with(lower(img_path), ".gz") ? "gzip" : "raw", want, 1);
  if (have < want)
    throw InvalidInput(path + ": the header declares " + describe(layout) + " (" + std::to_string(want) + " bytes with the offset) but " +
                       img_path + " holds " + std::to_string(have) + ": the volume is truncated or its header is wrong");
}

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

// One DICOM file's geometry and pixels.
struct Slice {
  std::string file;
  vtkSmartPointer<vtkImageData> pixels;
  Eigen::Vector3d position, row, column;
  double spacing[2] = {1, 1};
  double slope = 1, intercept = 0;
};

// A whole DICOM file, refused beyond 1 GB (no slice is that large).
std::string dicom_bytes(const std::string& f) {
  std::error_code ec;
  const std::uint64_t size = fs::file_size(f, ec);
  if (ec) throw IoError(f + ": cannot read the file");
  if (size > (std::uint64_t(1) << 30)) throw InvalidInput(f + ": " + std::to_string(size) + " bytes: too large for a DICOM slice");
  return file_head(f, std::size_t(size), false);
}

bool dicom_candidate(const fs::path& p) {
  if (lower(p.extension().string()) == ".dcm") return true;
  return looks_like_dicom(file_head(p.string(), 132, false));
}

Volume read_dicom_series(const std::string& input, std::size_t max_voxels) {
  // A file reads its own series (the files of its directory with its SeriesInstanceUID); a
  // directory must hold one series. Every file is checked (check_dicom_header) before VTK's
  // DICOM parser, which crashes or reads past its buffer on damaged headers, sees it.
  const bool from_file = !fs::is_directory(input);
  fs::path dir = from_file ? fs::path(input).parent_path() : fs::path(input);
  if (dir.empty()) dir = ".";
  std::string series;
  if (from_file) series = check_dicom_header(input, dicom_bytes(input)).series_uid;
  std::vector<std::string> files;
  std::map<std::string, std::string> series_found;  // UID -> a file of it
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = entry.path().filename().string();
    if (lower(name).rfind("dicomdir", 0) == 0 || name[0] == '.') continue;
    const std::string f = entry.path().string();
    if (!dicom_candidate(entry.path())) {
      // Scanners write slices without an extension. In a directory opened as a series, such a
      // file without the "DICM" marker is a damaged slice (the marker shifted or cut) far
      // more often than a stranger: dropping it would leave a silently shorter volume (a
      // slice lost at either end leaves no gap to notice). It must read as DICOM (some
      // files have no preamble) or the series is refused naming it.
      const std::string ext = lower(entry.path().extension().string());
      if (from_file || !(ext.empty() || ext == ".ima" || ext == ".dicom")) continue;
      try {
        check_dicom_header(f, dicom_bytes(f));
      } catch (const InvalidInput& e) {
        throw InvalidInput(std::string(e.what()) + "; in the DICOM series directory " + dir.string() +
                           " (remove the file, or open one of the series' files to read its series)");
      }
    }
    if (from_file && fs::equivalent(entry.path(), input)) {
      files.push_back(input);
      continue;
    }
    DicomHeader h;
    try {
      h = check_dicom_header(f, dicom_bytes(f));
    } catch (const InvalidInput&) {
      if (!from_file || series.empty()) throw;  // a directory's files must all read
      continue;  // a damaged file beside the one asked for: not known to be of its series
    }
    if (from_file && h.series_uid != series) continue;
    series_found.emplace(h.series_uid, f);
    files.push_back(f);
  }
  std::sort(files.begin(), files.end());
  const std::string where = dir.string();
  if (!from_file && series_found.size() > 1) {
    std::string list;
    for (const auto& [uid, f] : series_found) list += (list.empty() ? "" : ", ") + fs::path(f).filename().string();
    throw InvalidInput(where + ": holds " + std::to_string(series_found.size()) + " DICOM series (e.g. " + list +
                       "): open one of their files to read its series");
  }
  if (files.empty()) throw InvalidInput(where + ": no DICOM file in the directory");
  if (files.size() == 1)
    throw InvalidInput(files[0] + ": a single DICOM slice is not a volume (a series needs at least 2 slices" +
                       (from_file ? " of its SeriesInstanceUID" : "") + " in " + where + ")");
  if (files.size() > 4096) throw InvalidInput(where + ": " + std::to_string(files.size()) + " DICOM files, more than the 4096 slices accepted");
  std::vector<Slice> slices;
  for (const std::string& f : files) {
    vtkNew<vtkDICOMImageReader> reader;
    reader->SetFileName(f.c_str());
    ErrorCatcher errors(reader);
    ErrorCatcher pipeline(reader->GetExecutive());
    reader->UpdateInformation();
    if (errors.failed()) throw InvalidInput(f + ": " + errors.message());
    check_size(f, reader->GetDataExtent(), max_voxels);
    reader->Update();
    if (errors.failed()) throw InvalidInput(f + ": " + errors.message());
    vtkImageData* img = reader->GetOutput();
    if (!img || !img->GetPointData()->GetScalars()) throw InvalidInput(f + ": no pixel data read (compressed transfer syntax?)");
    if (img->GetNumberOfScalarComponents() != 1) throw InvalidInput(f + ": colour DICOM images are not volumes");
    Slice s;
    s.file = f;
    s.pixels = img;
    const float* ipp = reader->GetImagePositionPatient();
    const float* iop = reader->GetImageOrientationPatient();
    s.position = Eigen::Vector3d(ipp[0], ipp[1], ipp[2]);
    s.row = Eigen::Vector3d(iop[0], iop[1], iop[2]);
    s.column = Eigen::Vector3d(iop[3], iop[4], iop[5]);
    if (!(s.row.norm() > 0.5) || !(s.column.norm() > 0.5))
      throw InvalidInput(f + ": no ImageOrientationPatient (not a slice of a volume)");
    s.row.normalize();
    s.column.normalize();
    const double* ps = reader->GetPixelSpacing();
    s.spacing[0] = ps[0];
    s.spacing[1] = ps[1];
    s.slope = reader->GetRescaleSlope() != 0.0 ? reader->GetRescaleSlope() : 1.0;
    s.intercept = reader->GetRescaleOffset();
    slices.push_back(std::move(s));
  }
  const Slice& first = slices.front();
  int dims[3];
  first.pixels->GetDimensions(dims);
  for (const Slice& s : slices) {
    int d[3];
    s.pixels->GetDimensions(d);
    if (d[0] != dims[0] || d[1] != dims[1])
      throw InvalidInput(s.file + ": slice size " + std::to_string(d[0]) + " x " + std::to_string(d[1]) + " differs from " +
                         first.file + " (" + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + "): mixed series");
    if ((s.row - first.row).norm() > 1e-3 || (s.column - first.column).norm() > 1e-3)
      throw InvalidInput(s.file + ": slice orientation differs from " + first.file + ": mixed series (not one stack)");
    if (std::abs(s.spacing[0] - first.spacing[0]) > 1e-4 || std::abs(s.spacing[1] - first.spacing[1]) > 1e-4)
      throw InvalidInput(s.file + ": pixel spacing differs from " + first.file + ": mixed series");
    if (s.pixels->GetScalarType() != first.pixels->GetScalarType() || s.slope != first.slope || s.intercept != first.intercept)
      throw InvalidInput(s.file + ": pixel type or rescale differs from " + first.file + ": mixed series");
  }
  const Eigen::Vector3d normal = first.row.cross(first.column).normalized();
  std::sort(slices.begin(), slices.end(),
            [&](const Slice& a, const Slice& b) { return a.position.dot(normal) < b.position.dot(normal); });
  std::vector<double> steps;
  for (std::size_t k = 1; k < slices.size(); ++k) {
    const Eigen::Vector3d d = slices[k].position - slices[k - 1].position;
    const double step = d.dot(normal);
    if (step < 1e-3)
      throw InvalidInput(slices[k].file + ": at the same position as " + slices[k - 1].file + " (duplicate slice or two series)");
    if ((d - step * normal).norm() > 0.01 * step + 1e-3)
      throw InvalidInput(slices[k].file + ": slices are not stacked along their normal (sheared or mixed series)");
    steps.push_back(step);
  }
  std::vector<double> sorted = steps;
  std::sort(sorted.begin(), sorted.end());
  const double step = sorted[sorted.size() / 2];
  for (std::size_t k = 0; k < steps.size(); ++k) {
    if (std::abs(steps[k] - step) > 0.01 * step + 1e-3) {
      std::ostringstream msg;
      msg << slices[k + 1].file << ": " << steps[k] << " mm from the previous slice " << fs::path(slices[k].file).filename().string()
          << " where the series steps " << step << " mm: missing slices or mixed spacing in " << where;
      throw InvalidInput(msg.str());
    }
  }
  check_size(where, std::array<int, 6>{0, dims[0] - 1, 0, dims[1] - 1, 0, int(slices.size()) - 1}.data(), max_voxels);
  // Stack the slices (VTK's DICOM reader already turned each so that row 0 is the image's
  // last row: its origin is at the lower left).
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(dims[0], dims[1], int(slices.size()));
  image->AllocateScalars(first.pixels->GetScalarType(), 1);
  const std::size_t slice_bytes = std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(first.pixels->GetScalarSize());
  auto* dst = static_cast<unsigned char*>(image->GetScalarPointer());
  for (std::size_t k = 0; k < slices.size(); ++k)
    std::memcpy(dst + k * slice_bytes, slices[k].pixels->GetScalarPointer(), slice_bytes);
  Volume v;
  v.format = "DICOM series";
  v.image = image;
  v.index_to_mm = Eigen::Matrix4d::Identity();
  v.index_to_mm.block<3, 1>(0, 0) = first.row * first.spacing[0];
  v.index_to_mm.block<3, 1>(0, 1) = -first.column * first.spacing[1];
  v.index_to_mm.block<3, 1>(0, 2) = normal * step;
  v.index_to_mm.block<3, 1>(0, 3) = slices.front().position + first.column * first.spacing[1] * double(dims[1] - 1);
  // vtkDICOMImageReader already applies RescaleSlope / RescaleIntercept: the voxels are
  // calibrated (Hounsfield units for CT).
  v.facts["rescale_applied"] = {{"slope", first.slope}, {"intercept", first.intercept}};
  v.facts["slices"] = slices.size();
  v.facts["first_file"] = slices.front().file;
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

TriangleMesh volume_surface(const Volume& volume, const VolumeSurfaceOptions& options, const std::string& path,
                            nlohmann::json* facts) {
  if (options.iso && options.label) throw InvalidInput(path + ": give an iso-value or a label, not both");
  vtkDataArray* scalars = volume.image->GetPointData()->GetScalars();
  double range[2];
  scalars->GetRange(range, 0);
  const double lo = std::min(range[0] * volume.slope + volume.intercept, range[1] * volume.slope + volume.intercept);
  const double hi = std::max(range[0] * volume.slope + volume.intercept, range[1] * volume.slope + volume.intercept);
  vtkSmartPointer<vtkPolyData> surface;
  double stored_iso = 0;
  long label = 0;
  if (options.label) {
    label = *options.label;
    const double stored = (double(label) - volume.intercept) / volume.slope;
    bool present = false;
    const vtkIdType n = scalars->GetNumberOfTuples();
    for (vtkIdType i = 0; i < n && !present; ++i) present = scalars->GetComponent(i, 0) == stored;
    if (!present) {
      std::string have = volume.facts.contains("labels") ? " (labels present: " + volume.facts["labels"].dump() + ")" : "";
      throw InvalidInput(path + ": no voxel has label " + std::to_string(label) + have);
    }
    vtkNew<vtkDiscreteFlyingEdges3D> contour;
    contour->SetInputData(volume.image);
    contour->SetValue(0, stored);
    contour->ComputeNormalsOff();
    contour->ComputeGradientsOff();
    contour->ComputeScalarsOff();
    contour->Update();
    surface = contour->GetOutput();
    stored_iso = stored;
    if (facts) (*facts)["label"] = label;
  } else {
    double iso;
    if (options.iso) {
      iso = *options.iso;
      if (!std::isfinite(iso)) throw InvalidInput(path + ": the iso-value is not a finite number");
    } else {
      if (!(hi > lo)) throw InvalidInput(path + ": every voxel holds " + std::to_string(lo) + ": no surface in a constant volume");
      iso = otsu_threshold(volume_histogram(volume));  // the Surface panel's histogram and Otsu value
    }
    if (!(iso > lo && iso < hi)) {
      std::ostringstream msg;
      msg << path << ": no voxel crosses the iso-value " << iso << ": the values range from " << lo << " to " << hi;
      throw InvalidInput(msg.str());
    }
    stored_iso = (iso - volume.intercept) / volume.slope;
    vtkNew<vtkFlyingEdges3D> contour;
    contour->SetInputData(volume.image);
    contour->SetValue(0, stored_iso);
    contour->ComputeNormalsOff();
    contour->ComputeGradientsOff();
    contour->ComputeScalarsOff();
    contour->Update();
    surface = contour->GetOutput();
    if (facts) {
      (*facts)["iso"] = iso;
      (*facts)["iso_source"] = options.iso ? "--volume iso" : "automatic (Otsu threshold of the histogram; set --volume iso=V)";
    }
  }
  if (!surface || surface->GetNumberOfPolys() == 0)
    throw InvalidInput(path + ": the surface at " + (options.label ? "label " + std::to_string(label) : "the iso-value") + " is empty");
  if (facts) (*facts)["surface_triangles"] = surface->GetNumberOfPolys();

  // Voxel indices to millimetres.
  vtkPoints* points = surface->GetPoints();
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i) {
    double p[3];
    points->GetPoint(i, p);
    const Eigen::Vector4d q = volume.index_to_mm * Eigen::Vector4d(p[0], p[1], p[2], 1.0);
    points->SetPoint(i, q[0], q[1], q[2]);
  }
  surface->Modified();
  if (options.smooth_iterations > 0) {
    vtkNew<vtkWindowedSincPolyDataFilter> smooth;
    smooth->SetInputData(surface);
    smooth->SetNumberOfIterations(options.smooth_iterations);
    smooth->SetPassBand(0.1);
    smooth->NormalizeCoordinatesOn();
    smooth->BoundarySmoothingOff();
    smooth->FeatureEdgeSmoothingOff();
    smooth->NonManifoldSmoothingOn();
    smooth->Update();
    surface = smooth->GetOutput();
  }
  if (options.target_triangles > 0 && std::size_t(surface->GetNumberOfPolys()) > options.target_triangles) {
    vtkNew<vtkQuadricDecimation> decimate;
    decimate->SetInputData(surface);
    decimate->SetTargetReduction(1.0 - double(options.target_triangles) / double(surface->GetNumberOfPolys()));
    decimate->VolumePreservationOn();
    decimate->Update();
    surface = decimate->GetOutput();
  }
  TriangleMesh mesh;
  try {
    mesh = vtkHapticBoxUtilities::ToTriangleMesh(surface);
  } catch (const Error& e) {
    throw InvalidInput(path + ": " + e.what());
  }

  // Winding: normals out of the region at or above the iso-value (or inside the label).
  const Eigen::Matrix4d mm_to_index = volume.index_to_mm.inverse();
  double min_spacing = 1e30;
  for (int a = 0; a < 3; ++a) min_spacing = std::min(min_spacing, volume.index_to_mm.block<3, 1>(0, a).norm());
  int dims[3];
  volume.image->GetDimensions(dims);
  auto inside = [&](const Eigen::Vector3d& mm, bool& valid) {
    const Eigen::Vector4d q = mm_to_index * Eigen::Vector4d(mm.x(), mm.y(), mm.z(), 1.0);
    int ijk[3];
    for (int a = 0; a < 3; ++a) {
      ijk[a] = int(std::lround(q[a]));
      if (ijk[a] < 0 || ijk[a] >= dims[a]) {
        valid = false;
        return false;
      }
    }
    valid = true;
    const double x = scalars->GetComponent(volume.image->ComputePointId(ijk), 0);
    return options.label ? x == stored_iso : (volume.slope > 0 ? x >= stored_iso : x <= stored_iso);
  };
  long votes = 0;
  const std::size_t stride = std::max<std::size_t>(1, mesh.triangle_count() / 4000);
  for (std::size_t t = 0; t < mesh.triangle_count(); t += stride) {
    const Triangle& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.positions[tri[0]].cast<double>(), b = mesh.positions[tri[1]].cast<double>(),
                          c = mesh.positions[tri[2]].cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.norm() > 0)) continue;
    const Eigen::Vector3d centre = (a + b + c) / 3.0, step = n.normalized() * (0.75 * min_spacing);
    bool v1 = false, v2 = false;
    const bool ahead = inside(centre + step, v1), behind = inside(centre - step, v2);
    if (!v1 || !v2 || ahead == behind) continue;
    votes += ahead ? -1 : 1;
  }
  if (votes < 0) {
    for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  mesh.compute_vertex_normals();
  if (facts) (*facts)["triangles"] = mesh.triangle_count();
  return mesh;
}

} // namespace hb::vtk
