#pragma once
// A CT-like phantom with analytic surfaces, written in the volume formats HapticBox reads, so
// that isosurfaces can be checked against the exact surface (tests, datasets/generate_models).
#include <Eigen/Core>
#include <vtkSmartPointer.h>
#include <string>

class vtkImageData;

namespace hb::vtk {

/// Air (-1000 HU) around a soft-tissue ball (40 HU) holding a bone torus (700 HU), sampled on
/// an oblique, anisotropic grid. Each material's edge is a linear ramp of width
/// `edge_mm` across its analytic surface (the partial-volume blur of a scanner), so the
/// iso-value halfway between two materials lies exactly on the analytic surface.
struct CtPhantom {
  int dims[3] = {96, 96, 60};
  double spacing_mm[3] = {0.9, 0.9, 1.4};
  double body_radius_mm = 38.0;
  double torus_major_mm = 18.0;   ///< radius of the torus's centre circle (about the world z axis).
  double torus_minor_mm = 7.0;    ///< radius of its tube.
  double edge_mm = 1.6;           ///< width of the ramp between two materials (>= one voxel).
  Eigen::Vector3d centre_mm{12.0, -20.0, 35.0};  ///< world position of the ball's and torus's centre.
  double air_hu = -1000.0, soft_hu = 40.0, bone_hu = 700.0;

  /// Voxel index to world millimetres: a rotation (25 deg about z, then 10 deg about x) times the
  /// spacing, placed so that the grid's centre is at centre_mm.
  Eigen::Matrix4d index_to_mm() const;
  /// Signed distance (mm, negative inside) to the ball's and the torus's analytic surfaces.
  double body_distance(const Eigen::Vector3d& mm) const;
  double bone_distance(const Eigen::Vector3d& mm) const;
  /// Halfway iso-values: the ball's surface (air/soft) and the torus's (soft/bone).
  double body_iso() const { return 0.5 * (air_hu + soft_hu); }
  double bone_iso() const { return 0.5 * (soft_hu + bone_hu); }
};

/// The phantom's voxels (signed 16-bit HU) in index space (origin 0, spacing 1).
vtkSmartPointer<vtkImageData> make_ct_phantom(const CtPhantom& phantom);
/// Its label map (unsigned 8-bit: 0 air, 1 soft tissue, 2 bone), by voxel centre.
vtkSmartPointer<vtkImageData> make_phantom_labels(const CtPhantom& phantom);

/// Writes an index-space image with its voxel-to-millimetre matrix (a rotation times the
/// spacing, plus an offset): NIfTI (.nii, .nii.gz; qform and sform, unit mm), MetaImage (.mha,
/// TransformMatrix and Offset) or NRRD (.nrrd, space directions and space origin), by
/// extension. Throws hb::IoError on a write failure, hb::InvalidInput for another extension.
void write_volume(vtkImageData* image, const Eigen::Matrix4d& index_to_mm, const std::string& path);

} // namespace hb::vtk
