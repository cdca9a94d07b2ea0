// The CT phantom: values from the analytic signed distances through a linear edge ramp;
// writers for NIfTI (VTK's writer, qform and sform), MetaImage and NRRD (headers written here,
// since VTK 9.1's writers have no direction matrix).
#include "volume_phantom.h"
#include "string_util.h"
#include "errors.h"
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNIFTIImageHeader.h>
#include <vtkNIFTIImageWriter.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>

namespace hb::vtk {

namespace {

double ramp(double d, double width) { return std::clamp(0.5 - d / width, 0.0, 1.0); }

Eigen::Vector3d world(const Eigen::Matrix4d& m, int i, int j, int k) {
  return (m * Eigen::Vector4d(i, j, k, 1.0)).head<3>();
}

const char* met_type(int vtk_type) {
  switch (vtk_type) {
    case VTK_SHORT: return "MET_SHORT";
    case VTK_UNSIGNED_SHORT: return "MET_USHORT";
    case VTK_UNSIGNED_CHAR: return "MET_UCHAR";
    case VTK_CHAR: case VTK_SIGNED_CHAR: return "MET_CHAR";
    case VTK_INT: return "MET_INT";
    case VTK_FLOAT: return "MET_FLOAT";
    case VTK_DOUBLE: return "MET_DOUBLE";
    default: return nullptr;
  }
}

const char* nrrd_type(int vtk_type) {
  switch (vtk_type) {
    case VTK_SHORT: return "short";
    case VTK_UNSIGNED_SHORT: return "ushort";
    case VTK_UNSIGNED_CHAR: return "uchar";
    case VTK_CHAR: case VTK_SIGNED_CHAR: return "signed char";
    case VTK_INT: return "int";
    case VTK_FLOAT: return "float";
    case VTK_DOUBLE: return "double";
    default: return nullptr;
  }
}

void write_raw(std::ofstream& out, vtkImageData* image, const std::string& path) {
  const auto bytes = std::streamsize(image->GetNumberOfPoints() * image->GetScalarSize() * image->GetNumberOfScalarComponents());
  out.write(static_cast<const char*>(image->GetScalarPointer()), bytes);
  if (!out) throw IoError(path + ": write failed");
}

} // namespace

Eigen::Matrix4d CtPhantom::index_to_mm() const {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(10.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(25.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 3>(0, 0) = r * Eigen::Vector3d(spacing_mm[0], spacing_mm[1], spacing_mm[2]).asDiagonal();
  const Eigen::Vector3d mid(0.5 * (dims[0] - 1), 0.5 * (dims[1] - 1), 0.5 * (dims[2] - 1));
  m.block<3, 1>(0, 3) = centre_mm - m.block<3, 3>(0, 0) * mid;
  return m;
}

double CtPhantom::body_distance(const Eigen::Vector3d& mm) const { return (mm - centre_mm).norm() - body_radius_mm; }

double CtPhantom::bone_distance(const Eigen::Vector3d& mm) const {
  const Eigen::Vector3d p = mm - centre_mm;
  const double ring = std::hypot(p.x(), p.y()) - torus_major_mm;
  return std::hypot(ring, p.z()) - torus_minor_mm;
}

vtkSmartPointer<vtkImageData> make_ct_phantom(const CtPhantom& phantom) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(phantom.dims);
  image->AllocateScalars(VTK_SHORT, 1);
  auto* v = static_cast<short*>(image->GetScalarPointer());
  const Eigen::Matrix4d m = phantom.index_to_mm();
  std::size_t at = 0;
  for (int k = 0; k < phantom.dims[2]; ++k)
    for (int j = 0; j < phantom.dims[1]; ++j)
      for (int i = 0; i < phantom.dims[0]; ++i) {
        const Eigen::Vector3d p = world(m, i, j, k);
        const double hu = phantom.air_hu + (phantom.soft_hu - phantom.air_hu) * ramp(phantom.body_distance(p), phantom.edge_mm) +
                          (phantom.bone_hu - phantom.soft_hu) * ramp(phantom.bone_distance(p), phantom.edge_mm);
        v[at++] = short(std::lround(hu));
      }
  return image;
}

vtkSmartPointer<vtkImageData> make_phantom_labels(const CtPhantom& phantom) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(phantom.dims);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = static_cast<unsigned char*>(image->GetScalarPointer());
  const Eigen::Matrix4d m = phantom.index_to_mm();
  std::size_t at = 0;
  for (int k = 0; k < phantom.dims[2]; ++k)
    for (int j = 0; j < phantom.dims[1]; ++j)
      for (int i = 0; i < phantom.dims[0]; ++i) {
        const Eigen::Vector3d p = world(m, i, j, k);
        v[at++] = phantom.bone_distance(p) < 0 ? 2 : phantom.body_distance(p) < 0 ? 1 : 0;
      }
  return image;
}

void write_volume(vtkImageData* image, const Eigen::Matrix4d& index_to_mm, const std::string& path) {
  const std::string p = lower(path);
  Eigen::Matrix3d dir = index_to_mm.block<3, 3>(0, 0);
  double spacing[3];
  for (int a = 0; a < 3; ++a) {
    spacing[a] = dir.col(a).norm();
    dir.col(a) /= spacing[a];
  }
  const Eigen::Vector3d origin = index_to_mm.block<3, 1>(0, 3);
  int dims[3];
  image->GetDimensions(dims);
  if (ends_with(p, ".nii") || ends_with(p, ".nii.gz")) {
    vtkNew<vtkImageData> copy;
    copy->ShallowCopy(image);
    copy->SetSpacing(spacing);
    copy->SetOrigin(0, 0, 0);
    vtkNew<vtkMatrix4x4> m;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m->SetElement(r, c, dir(r, c));
      m->SetElement(r, 3, origin[r]);
    }
    vtkNew<vtkNIFTIImageHeader> header;
    header->SetXYZTUnits(2 | 8);  // mm, s
    vtkNew<vtkNIFTIImageWriter> writer;
    writer->SetInputData(copy);
    writer->SetFileName(path.c_str());
    writer->SetNIFTIHeader(header);
    writer->SetQFormMatrix(m);
    writer->SetSFormMatrix(m);
    writer->Write();
    if (writer->GetErrorCode() != 0) throw IoError(path + ": the NIfTI writer failed");
    return;
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) throw IoError(path + ": cannot create the file");
  out.precision(17);
  if (ends_with(p, ".mha")) {
    const char* type = met_type(image->GetScalarType());
    if (!type) throw InvalidInput(path + ": no MetaImage type for " + image->GetScalarTypeAsString());
    out << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\nCompressedData = False\n";
    out << "TransformMatrix =";
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) out << ' ' << dir(r, a);
    out << "\nOffset = " << origin.x() << ' ' << origin.y() << ' ' << origin.z() << "\nCenterOfRotation = 0 0 0\n";
    out << "AnatomicalOrientation = RAI\nElementSpacing = " << spacing[0] << ' ' << spacing[1] << ' ' << spacing[2] << "\n";
    out << "DimSize = " << dims[0] << ' ' << dims[1] << ' ' << dims[2] << "\nElementType = " << type
        << "\nElementDataFile = LOCAL\n";
    write_raw(out, image, path);
    return;
  }
  if (ends_with(p, ".nrrd")) {
    const char* type = nrrd_type(image->GetScalarType());
    if (!type) throw InvalidInput(path + ": no NRRD type for " + image->GetScalarTypeAsString());
    out << "NRRD0004\ntype: " << type << "\ndimension: 3\nspace: left-posterior-superior\nsizes: " << dims[0] << ' '
        << dims[1] << ' ' << dims[2] << "\nspace directions:";
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d d = index_to_mm.block<3, 1>(0, a);
      out << " (" << d.x() << ',' << d.y() << ',' << d.z() << ')';
    }
    out << "\nkinds: domain domain domain\nendian: little\nencoding: raw\nspace origin: (" << origin.x() << ','
        << origin.y() << ',' << origin.z() << ")\n\n";
    write_raw(out, image, path);
    return;
  }
  throw InvalidInput(path + ": write_volume writes .nii, .nii.gz, .mha or .nrrd");
}

} // namespace hb::vtk
