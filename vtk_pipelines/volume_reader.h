#pragma once
// Medical volumes (NIfTI, MetaImage, NRRD, DICOM series) read through VTK, and the surface a
// haptic model is baked from: an isosurface (flying edges) or a label's boundary (discrete
// flying edges), optionally smoothed and decimated, in millimetres of the patient.
#include "mesh/triangle_mesh.h"
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <vtkSmartPointer.h>
#include <cstddef>
#include <optional>
#include <string>

class vtkImageData;

namespace hb::vtk {

/// How a volume becomes a surface.
struct VolumeSurfaceOptions {
  /// Iso-value in the file's calibrated units (Hounsfield units for CT: the rescale slope and
  /// intercept are applied). Neither iso nor label: the Otsu threshold of the value histogram.
  std::optional<double> iso;
  /// Label of a label map: the boundary of the voxels holding exactly this value.
  std::optional<long> label;
  /// Windowed-sinc smoothing iterations (0: none; 10-30 removes voxel steps, moves the
  /// surface by well under a voxel).
  int smooth_iterations = 0;
  /// Quadric decimation down to about this many triangles (0: keep every triangle).
  std::size_t target_triangles = 0;
  /// Volumes with more voxels are refused before their data is read.
  std::size_t max_voxels = std::size_t(1) << 30;
};

/// A volume in index space plus the map to patient millimetres.
struct Volume {
  /// Scalars, origin 0, spacing 1: point (i, j, k) is voxel (i, j, k).
  vtkSmartPointer<vtkImageData> image;
  /// Voxel index (i, j, k, 1) to millimetres in the file's world frame (RAS for NIfTI, LPS for
  /// DICOM, MetaImage and NRRD): direction x spacing, plus the origin. Spacing and orientation
  /// (NIfTI sform/qform, DICOM ImageOrientationPatient, MetaImage TransformMatrix, NRRD space
  /// directions) are all in it.
  Eigen::Matrix4d index_to_mm{Eigen::Matrix4d::Identity()};
  double slope = 1.0;       ///< calibrated value = slope * stored + intercept.
  double intercept = 0.0;
  std::string format;       ///< "NIfTI", "MetaImage", "NRRD", "DICOM series".
  nlohmann::json facts;     ///< dimensions, spacing_mm, origin_mm, direction, value_range, labels...
};

/// True for the extensions read_volume takes (.nii .nii.gz .hdr .mha .mhd .nrrd .nhdr .dcm) and
/// for a directory (a DICOM series).
bool is_volume_path(const std::string& path);

/// Reads a volume. A DICOM series is a directory (or one of its .dcm files): every DICOM file
/// in it, sorted along the slice normal; the slices must share size, pixel spacing and
/// orientation and be evenly spaced. Throws hb::IoError (missing, unreadable) or
/// hb::InvalidInput (unknown format, more than `max_voxels`, zero/NaN spacing, a single slice,
/// missing slices or mixed spacing, mixed orientation); the message names the file and cause.
Volume read_volume(const std::string& path, std::size_t max_voxels = std::size_t(1) << 30);

/// The surface of `volume` per `options`, in millimetres, oriented with its normals pointing
/// out of the bright (or labelled) region. Adds the iso-value or label used and the triangle
/// counts to `facts` when given. Throws hb::InvalidInput naming `path` when no voxel reaches
/// the iso-value, the label is absent, or the surface is empty.
TriangleMesh volume_surface(const Volume& volume, const VolumeSurfaceOptions& options, const std::string& path,
                            nlohmann::json* facts = nullptr);

} // namespace hb::vtk
