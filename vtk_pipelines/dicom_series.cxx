// A DICOM series as one volume:
//  1. the series' files: a directory's (one series; an extension-less file without the DICM
//     marker is a damaged slice, not a stranger) or a file's (its SeriesInstanceUID);
//  2. every file checked (check_dicom_header), then read by VTK one slice at a time;
//  3. the slices held to the first (size, orientation, spacing, pixel type, rescale), sorted
//     along their normal and held to one step (the median): a gap or a duplicate is named;
//  4. stacked into one image whose index_to_mm is built from the first slice's geometry.
#include "dicom_series.h"
#include "errors.h"
#include "string_util.h"
#include "volume_data_check.h"
#include "vtk_error_catcher.h"
#include "formats/dicom_header.h"
#include <vtkDICOMImageReader.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <vector>

namespace hb::vtk {

namespace {

namespace fs = std::filesystem;
using hb::DicomHeader;

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

// The files of the series `input` names (sorted), and the directory they are in.
std::vector<std::string> series_files(const std::string& input, std::string& where) {
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
  where = dir.string();
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
  return files;
}

// One file read by VTK's DICOM reader, with its geometry.
Slice read_slice(const std::string& f, std::size_t max_voxels) {
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
  return s;
}

// Every slice as the first: size, orientation, pixel spacing, pixel type and rescale.
void check_same_slices(const std::vector<Slice>& slices) {
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
}

// Sorts the slices along `normal` and returns the series' step (the median): every step must
// be it (a gap is a missing slice), stacked along the normal.
double sort_and_step(std::vector<Slice>& slices, const Eigen::Vector3d& normal, const std::string& where) {
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
  return step;
}

// The sorted slices stacked into one volume (VTK's DICOM reader already turned each so that
// row 0 is the image's last row: its origin is at the lower left).
Volume stack_slices(const std::vector<Slice>& slices, const Eigen::Vector3d& normal, double step) {
  const Slice& first = slices.front();
  int dims[3];
  first.pixels->GetDimensions(dims);
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

Volume read_dicom_series(const std::string& input, std::size_t max_voxels) {
  std::string where;
  const std::vector<std::string> files = series_files(input, where);
  std::vector<Slice> slices;
  for (const std::string& f : files) slices.push_back(read_slice(f, max_voxels));
  check_same_slices(slices);
  const Eigen::Vector3d normal = slices.front().row.cross(slices.front().column).normalized();
  const double step = sort_and_step(slices, normal, where);
  int dims[3];
  slices.front().pixels->GetDimensions(dims);
  check_size(where, std::array<int, 6>{0, dims[0] - 1, 0, dims[1] - 1, 0, int(slices.size()) - 1}.data(), max_voxels);
  return stack_slices(slices, normal, step);
}

} // namespace hb::vtk
